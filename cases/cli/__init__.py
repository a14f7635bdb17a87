"""The ``coinwall`` command line: thin subcommands that parse, call the library, print or write."""

from .main import main

__all__ = ["main"]
