"""Lazy package namespaces (SPEC 1): each package's ``__init__.pyi`` stub is its table of public names.

``attach_stub(__name__, __file__)`` in a package's ``__init__.py`` reads the stub beside it with
lazy_loader (the Scientific Python reference implementation of SPEC 1) and returns ``__getattr__``,
``__dir__`` and ``__all__``: a public name is imported from the module the stub names on its first use,
so importing a package imports none of its modules, and editors and type checkers read the same stub
(go-to-definition).  ``EAGER_IMPORT=1`` in the environment imports every name at once (lazy_loader's
switch, for finding a broken import).
"""

import sys

import lazy_loader

__all__ = ["attach_stub"]


def attach_stub(package: str, filename: str):
    """``(__getattr__, __dir__, __all__)`` of ``package`` from the ``__init__.pyi`` beside ``filename``.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    filename : str
        Its ``__init__.py`` (``__file__``).

    Returns
    -------
    tuple
        ``__getattr__`` (an unknown name raises AttributeError in Python's own words), ``__dir__`` (the
        public names and what the package already holds) and ``__all__`` (the public names, sorted).
    """
    load, _, names = lazy_loader.attach_stub(package, filename)
    public = frozenset(names)

    def __getattr__(name):
        if name in public:
            return load(name)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(public | set(vars(sys.modules[package])))

    return __getattr__, __dir__, list(names)
