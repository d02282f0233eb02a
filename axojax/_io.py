"""Output files written whole: a temporary name in the target directory, then a rename.

Every file axojax writes (sweep results and their chunks, simulations, orbit branches,
posteriors, figures (:func:`save_figure`), animations, NetCDF, text
(:func:`write_text`)) goes through :func:`atomic_path`: the writer fills a
temporary file next to the target, named per process (``.NAME.PID.RANDOM.tmp.SUFFIX``,
so two processes never share one), and ``os.replace`` renames it onto the target only
when the writer returned. A process killed at any moment (``kill -9``) leaves either no
file or the previous complete one, never a truncated one; the temporary file it leaves
behind is removed by the next write to the same target (its process is gone).

:func:`check_output_path` is the one rule every command applies to its output paths
before any work: the suffix must be one the command writes, the directory must exist
(it is never created) and accept a new file, and the path must not be a directory.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import pathlib
import secrets
from collections.abc import Iterator

TMP_MARK = ".tmp"


class OutputBusy(RuntimeError):
    """Another process is writing the same output (its lock is held)."""


def _tmp_name(path: pathlib.Path) -> pathlib.Path:
    # the real suffix last, in lower case: numpy appends ".npz" to a name not ending in
    # exactly that (so "x.NPZ" would be written elsewhere), matplotlib picks its writer by it
    return path.with_name(
        f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}{TMP_MARK}{path.suffix.lower()}"
    )


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale_temporaries(path: str | os.PathLike) -> list[pathlib.Path]:
    """Remove temporary files of ``path`` left by processes that no longer run (a
    ``kill -9`` during a write). Returns what was removed."""
    path = pathlib.Path(path)
    removed = []
    for tmp in path.parent.glob(f".{path.name}.*{TMP_MARK}{path.suffix.lower()}"):
        parts = tmp.name[len(path.name) + 2 :].split(".")
        if len(parts) >= 2 and parts[0].isdigit() and not _pid_alive(int(parts[0])):
            with contextlib.suppress(OSError):
                tmp.unlink()
                removed.append(tmp)
    return removed


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[pathlib.Path]:
    """A temporary path to write instead of ``path``; renamed onto ``path`` when the
    block ends without an exception, removed otherwise.

    >>> with atomic_path("result.npz") as tmp:   # doctest: +SKIP
    ...     np.savez(tmp, x=x)
    """
    path = pathlib.Path(path)
    remove_stale_temporaries(path)
    tmp = _tmp_name(path)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def write_text(path: str | os.PathLike, text: str) -> None:
    """``path.write_text(text)``, atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text)


def save_figure(fig, path: str | os.PathLike, **kwargs) -> None:
    """``fig.savefig(path, **kwargs)``, atomically; the format is the target's suffix
    (matplotlib's default format for a path without one)."""
    import matplotlib

    fmt = pathlib.Path(path).suffix[1:].lower() or matplotlib.rcParams["savefig.format"]
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=kwargs.pop("format", fmt), **kwargs)


def check_output_path(path: str | os.PathLike, suffixes: tuple[str, ...]) -> pathlib.Path:
    """The one rule for output paths (module docstring); raises ``ValueError`` with one
    line saying what is wrong (without the flag: the caller adds it)."""
    p = pathlib.Path(path)
    if suffixes and p.suffix.lower() not in suffixes:
        raise ValueError(f"expected a {' or '.join(suffixes)} path, got {str(path)!r}")
    if p.is_dir():
        raise ValueError(f"{str(path)!r} is a directory")
    parent = p.parent if str(p.parent) else pathlib.Path(".")
    if not parent.exists():
        raise ValueError(
            f"directory {str(parent)!r} of {str(path)!r} does not exist (it is not created)"
        )
    if not parent.is_dir():
        raise ValueError(f"{str(parent)!r} in {str(path)!r} is not a directory")
    probe = parent / f".{p.name}.{os.getpid()}.{secrets.token_hex(4)}.probe"
    try:
        fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except OSError as err:
        raise ValueError(
            f"cannot write in directory {str(parent)!r} ({err.strerror or err})"
        ) from None
    os.close(fd)
    with contextlib.suppress(OSError):
        probe.unlink()
    if p.exists() and not os.access(p, os.W_OK):
        raise ValueError(f"{str(path)!r} exists and is not writable")
    return p


@contextlib.contextmanager
def exclusive(lock: str | os.PathLike, what: str) -> Iterator[None]:
    """Hold an exclusive ``flock`` on the file ``lock`` for the block; raise
    :class:`OutputBusy` at once when another process holds it (released by the kernel
    when that process ends, even by ``kill -9``)."""
    lock = pathlib.Path(lock)
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise OutputBusy(
                f"another process is writing {what} (lock {str(lock)!r} is held); wait for it, or choose another path"
            ) from None
        # the holder before us may have removed the file after we opened it: retry then
        try:
            same = os.fstat(fd).st_ino == os.stat(lock).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.write(fd, f"{os.getpid()}\n".encode())
        yield
    finally:
        with contextlib.suppress(OSError):
            lock.unlink()
        os.close(fd)
