"""Output files: atomic writes (a temporary file, then one rename), writable folders, image file names."""

from __future__ import annotations

import os
import secrets
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

from ._checks import as_path


@contextmanager
def atomic_path(path):
    """A temporary file beside ``path`` to write to; it replaces ``path`` only when the block succeeds.

    The temporary file is in the same folder (so ``os.replace`` is one atomic
    rename) and keeps the suffix (so writers that choose the format by the
    extension, such as matplotlib, still do). If the block raises, the
    temporary file is removed and ``path`` is left as it was: a reader never
    sees a half-written file.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.

    Yields
    ------
    Path
        The temporary file (it exists, empty).

    Raises
    ------
    IsADirectoryError
        If ``path`` is a folder, or a name ending with ``/``.
    FileNotFoundError
        If its folder does not exist.
    NotADirectoryError
        If its folder is a file.
    OSError
        If no file can be written in its folder (no permission, a read-only
        file system), naming ``path``.
    ValueError
        If it exists and is not a regular file (a device such as
        ``/dev/null``, a pipe): the rename would replace it. A symbolic link
        is followed: its target is written and the link kept.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> with atomic_path(folder / "out.txt") as tmp:
    ...     _ = tmp.write_text("done")
    >>> (folder / "out.txt").read_text(), sorted(p.name for p in folder.iterdir())
    ('done', ['out.txt'])
    """
    given, path = path, as_path(path, "an output path")
    if isinstance(given, str) and given.endswith(("/", os.sep)):  # (Path drops the separator)
        raise IsADirectoryError(f"cannot write '{given}': a name ending with '/' is a folder's; give a file name")
    path = path.resolve() if path.is_symlink() else path  # a link's target is written, the link kept
    if path.is_dir():
        raise IsADirectoryError(f"cannot write '{path}': it is a folder; give a file name")
    if path.exists() and not path.is_file():
        raise ValueError(f"cannot write '{path}': it is not a regular file (a device, a pipe or a socket), which "
                         "a saved file would replace; give a file name")
    if path.parent.exists() and not path.parent.is_dir():
        raise NotADirectoryError(f"cannot write '{path}': '{path.parent}' is a file, not a folder")
    if not path.parent.is_dir():
        raise FileNotFoundError(f"cannot write '{path}': the folder '{path.parent}' does not exist")
    while True:  # like tempfile.mkstemp, but the file gets the usual permissions (0o666 less the umask)
        tmp = path.with_name(f".{path.stem[:64]}.{secrets.token_hex(4)}.tmp{path.suffix[:16]}")  # (names <= 255)
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            break
        except FileExistsError:
            continue
        except OSError as exc:  # (no permission, a read-only file system): named by the file asked for
            raise type(exc)(exc.errno, f"cannot write '{path}' ({exc.strerror}: a file is first written beside it, "
                                       "then renamed)") from None
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def writable_folder(path, what: str = "output folder") -> Path:
    """Create ``path`` if needed and check that a file can be written in it.

    Parameters
    ----------
    path : str or os.PathLike
        The folder.
    what : str
        How the folder is named in the error message.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If the folder cannot be created or written to (the message names the
        folder and the reason), or its name is empty.
    TypeError
        If ``path`` is not a str or os.PathLike.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> writable_folder(Path(tempfile.mkdtemp()) / "new" / "folder").is_dir()
    True
    """
    if isinstance(path, (str, bytes)) and not path:
        raise ValueError(f"the {what} is an empty name (an unset variable?): name a folder, '.' for the current one")
    path = as_path(path, f"the {what}")
    try:
        path.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=".write-check.", dir=path)
        os.close(fd)
        os.unlink(name)
    except OSError as exc:
        reason = (exc.strerror or str(exc)).lower()
        if path.exists() and not path.is_dir():
            reason = "it is a file, not a folder"
        raise ValueError(f"cannot write to the {what} '{path}' ({reason}); choose a writable folder") from None
    return path


def image_path(path, suffixes=None) -> Path:
    """``Path(path)``; ValueError unless its extension is an image format matplotlib writes (or one of ``suffixes``).

    Parameters
    ----------
    path : str or os.PathLike
    suffixes : list of str, optional
        The extensions allowed (e.g. ``[".gif"]``); default matplotlib's.

    Returns
    -------
    Path
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    path = as_path(path, "the image path")
    known = suffixes or sorted(f".{ext}" for ext in FigureCanvasAgg.get_supported_filetypes()
                               if ext != "pgf" or shutil.which("xelatex"))  # (pgf needs a TeX installation)
    if path.suffix.lower() not in known:
        raise ValueError(f"cannot write '{path}': {path.suffix or 'no extension'} is not a supported format; "
                         f"use one of {', '.join(known)}")
    return path
