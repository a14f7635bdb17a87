"""Small file helpers shared by every writer: outputs are written to a temporary file and renamed."""

import os

__all__ = ["default_file_mode"]


def default_file_mode() -> int:
    """The mode a plain ``open(path, "w")`` would give (0o666 minus the umask).

    ``tempfile.mkstemp`` creates files readable by their owner only; outputs renamed from such a
    temporary file would otherwise surprise users (and web servers) with mode 0600.
    """
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask
