"""Writing results so that a run that fails or is interrupted leaves the files it would replace as they
were: each file is written under a temporary name beside it (.NAME.tmp) and renamed over its own name
only once it is complete (os.replace, atomic on one file system). A command that fails never leaves a
finished result replaced by an empty or a partial one.
"""
import contextlib
import os
import pathlib


def temporary(path):
    """The temporary name beside path that replacing() writes first."""
    path = pathlib.Path(path)
    return path.with_name(f".{path.name}.tmp")


@contextlib.contextmanager
def replacing(path, mode="w", opener=open, **options):
    """with replacing(path) as fh: write fh; path is replaced when the block ends without an exception
    (KeyboardInterrupt included); otherwise the temporary file is removed and path keeps what it held.
    opener: open, or gzip.open for a compressed file (mode and options go to it)."""
    path = pathlib.Path(path)
    tmp = temporary(path)
    try:
        with opener(tmp, mode, **options) as fh:
            yield fh
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)   # only there when the block failed


def write_text(path, text):
    """path holds text (replaced at once)."""
    with replacing(path) as fh:
        fh.write(text)
    return path


def save_figure(fig, path, dpi):
    """fig as an image at path (the format from its suffix, PNG when none), replaced at once."""
    path = pathlib.Path(path)
    with replacing(path, "wb") as fh:
        fig.savefig(fh, dpi=dpi, format=path.suffix.lstrip(".") or "png")
    return path
