"""How sphinx-gallery draws and saves the gallery's figures: in the house style, at publication size.

Named in ``docs/conf.py`` by their dotted names (sphinx-gallery imports them; the configuration stays
picklable):

* :func:`reset` runs before every example, after matplotlib's own reset: the house style's rcParams
  (:data:`coinwall.forward.formats.style.HOUSE_STYLE`), so the gallery looks like the command line's figures;
* :func:`scraper` saves each figure of an example as sphinx-gallery's matplotlib scraper does, at the
  resolution that makes it at least ``PNG_MIN_WIDTH`` pixels wide (:func:`coinwall.forward.formats.figure.png_dpi`),
  after checking that no legend covers a text (:func:`coinwall.forward.formats.style.legend_overlaps`):
  a figure that fails stops the build, naming the example and what is covered.
"""

from __future__ import annotations


def reset(gallery_conf, fname):
    """Apply the house style's rcParams for the next example."""
    import matplotlib

    from coinwall.forward.formats.style import HOUSE_STYLE

    matplotlib.rcParams.update(HOUSE_STYLE)


def scraper(block, block_vars, gallery_conf, **kwargs):
    """sphinx-gallery's matplotlib scraper at publication size, refusing a legend that covers a text."""
    import matplotlib.pyplot as plt
    from sphinx_gallery.scrapers import matplotlib_scraper

    from coinwall.forward.formats.figure import png_dpi
    from coinwall.forward.formats.style import legend_overlaps

    figures = [plt.figure(num) for num in plt.get_fignums()]
    for fig in figures:
        problems = legend_overlaps(fig)
        if problems:
            raise RuntimeError(f"{block_vars.get('src_file', 'an example')}: " + "; ".join(problems))
    if figures:  # one resolution for the block's figures: the largest any of them needs
        kwargs.setdefault("dpi", max(png_dpi(fig) for fig in figures))
    return matplotlib_scraper(block, block_vars, gallery_conf, **kwargs)
