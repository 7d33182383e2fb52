"""Atomic file writes for every file the project writes (figures, JSON, the report).

The content goes to a temporary file in the target's folder, which is then renamed onto the target:
a reader sees the old file or the complete new one, never a part. The new file gets the permissions
a plain open() would give it (0666 less the umask), not the temporary file's 0600.
"""
from contextlib import contextmanager, suppress
import os
import tempfile


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextmanager
def atomic_write(path, mode="w"):
    """Open a temporary file beside `path` for writing (text "w" or binary "wb"); when the block ends
    without an error it replaces `path`, otherwise it is removed."""
    path = os.fspath(path)
    name = os.path.basename(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=os.path.splitext(name)[1],
                               dir=os.path.dirname(os.path.abspath(path)))
    try:
        with os.fdopen(fd, mode) as handle:
            yield handle
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        with suppress(OSError):
            os.unlink(tmp)
        raise
