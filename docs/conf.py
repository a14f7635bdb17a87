"""Sphinx configuration of the coinwall documentation site.

Build (warnings are errors)::

    pip install -e ".[docs]"
    python -m sphinx -W --keep-going -b html docs docs/_build/html

The Markdown pages are read by myst-parser, the API reference is autosummary + numpydoc over the public
names (``docs/api/``), and the gallery is sphinx-gallery over ``examples/`` (every ``examples/plot_*.py``
is run during the build).
"""

import os
import sys
import warnings

import coinwall  # installed with `pip install -e .`

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # gallery_house.py: the gallery's figures

# -- project -------------------------------------------------------------------------------------------------
project = "coinwall"
author = "the coinwall authors"
copyright = "coinwall authors, MIT licence"
release = coinwall.__version__
version = ".".join(release.split(".")[:2])

# -- extensions ----------------------------------------------------------------------------------------------
extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",   # MathJax 3 served from the site's own _static/mathjax: math renders offline
    "sphinx.ext.viewcode",
    "sphinx.ext.intersphinx",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "api/generated/*.examples"]
templates_path = ["_templates"]

# -- MyST (the existing Markdown pages) ------------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 4          # the pages link to their own sections as GitHub slugs (#units-and-conventions)
myst_dmath_double_inline = True

# -- API reference -----------------------------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "inherited-members": False}   # bases: only for the errors
autodoc_typehints = "none"         # numpydoc renders the Parameters sections; signatures stay short
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()

intersphinx_mapping = {}

# -- sphinx-gallery ----------------------------------------------------------------------------------------------
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMP_NUM_THREADS", "1")

sphinx_gallery_conf = {
    "examples_dirs": ["../examples"],
    "gallery_dirs": ["auto_examples"],
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    # the house style, and each figure at least 1600 px wide with no legend over a text (docs/gallery_house.py)
    "reset_modules": ("matplotlib", "gallery_house.reset"),
    "image_scrapers": ("gallery_house.scraper",),
    "abort_on_example_error": True,
    "show_memory": False,
    "thumbnail_size": (560, 240),
}

# numba / dask chatter must not turn into Sphinx warnings
warnings.filterwarnings("ignore", category=UserWarning, message="Matplotlib is currently using agg")

# -- HTML ------------------------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"coinwall {release}"
html_static_path = ["_static"]
html_css_files = ["coinwall.css"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 5,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_context = {"default_mode": "light"}
html_show_sourcelink = False
html_sidebars = {"auto_examples/index": []}   # the gallery cards get the whole width

