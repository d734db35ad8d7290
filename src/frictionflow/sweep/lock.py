"""One run at a time per sweep output: a lock file beside it, ``OUT.lock``.

The lock is an exclusive ``flock`` on ``OUT.lock``, which records who holds
it (PID, host, process start time, when it started).  The kernel drops a
``flock`` when its process dies, however it dies, so on one machine a lock
file whose ``flock`` is free is stale (SIGKILL, power loss) and is taken over
with a warning.  A lock written by another host (a shared file system, where
``flock`` may not reach across machines) counts as held while its holder
keeps touching it (every :data:`HEARTBEAT` seconds) and as stale once it is
older than ``stale_after`` seconds (:data:`STALE_AFTER`, 10 minutes).  Where
the file system has no ``flock`` at all, a lock on this host is stale when
its PID is gone, or now belongs to a process started at another time.
"""

from __future__ import annotations

import errno
import json
import os
import socket
import threading
import time
import warnings
from datetime import datetime, timezone
from pathlib import Path

from ..io import write_error

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: PID checks only
    fcntl = None

#: seconds between touches of a held lock (what tells other hosts it is alive)
HEARTBEAT = 30.0
#: seconds after which another host's untouched lock is stale
STALE_AFTER = 600.0
#: errors of flock on file systems without it: fall back to PID checks
_NO_FLOCK = (errno.ENOLCK, errno.EOPNOTSUPP, errno.EINVAL, errno.ENOSYS)


class OutputInUseError(RuntimeError):
    """Another run holds the output's lock (a runtime condition: exit code 1)."""


class StaleLockWarning(UserWarning):
    """A lock left by a run that is gone was taken over."""


def lock_path(out: str | Path) -> Path:
    """The lock file of output ``out``: ``OUT.lock`` in the same directory."""
    out = Path(out)
    return out.with_name(out.name + ".lock")


def _proc_start(pid: int) -> str | None:
    """The start time of process ``pid`` in clock ticks since boot (Linux), to tell a reused PID."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
        return stat.rsplit(")", 1)[1].split()[19]
    except (OSError, IndexError):
        return None


def _alive(pid, start: str | None) -> bool:
    """Whether ``pid`` runs and, when its start time is known, is the same process."""
    try:
        pid = int(pid)
        if pid <= 0:
            return False
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        pass  # someone else's process: it exists
    except (OverflowError, ValueError, TypeError):
        return False
    now = _proc_start(pid)
    return start is None or now is None or now == start


def _describe(info: dict) -> str:
    """``PID N (started T)``, with the host when it is not this one."""
    host = info.get("host")
    where = f" on host {host}" if host and host != socket.gethostname() else ""
    return f"PID {info.get('pid', '?')}{where} (started {info.get('started', 'at an unknown time')})"


class SweepLock:
    """An exclusive lock on a sweep output; a context manager.

    ``with SweepLock(out):`` fails at once with :class:`OutputInUseError`
    when another live run holds it, and releases it on every exit (normal
    return, exception, KeyboardInterrupt).
    """

    def __init__(self, out: str | Path, stale_after: float = STALE_AFTER, name: str = "out") -> None:
        self.out = Path(out)
        self.name = name  #: how messages name the output (the command line's option)
        self.path = lock_path(out)
        self.stale_after = stale_after
        self._fd: int | None = None
        self._stop = threading.Event()
        self._beat: threading.Thread | None = None

    # -- acquire ---------------------------------------------------------------
    def acquire(self) -> None:
        """Take the lock, or raise :class:`OutputInUseError` naming its holder."""
        for _ in range(20):  # a holder releasing (unlinking) as we open: open again
            fd = self._open()
            try:
                flocked = self._flock(fd)
                if os.fstat(fd).st_ino != _inode(self.path):
                    os.close(fd)
                    continue
                self._take(fd, flocked)
            except OSError as e:  # our record could not be written (a full disk): the file is ours to remove
                self._abandon(fd, flocked)
                raise write_error(e, self.name, self.path, "nothing was computed or written") from None
            except BaseException:
                os.close(fd)
                raise
            self._fd = fd
            self._start_heartbeat()
            return
        raise OutputInUseError(f"{self.out} is in use: its lock {self.path} keeps changing")

    def _open(self) -> int:
        try:
            return os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as e:
            raise write_error(e, self.name, self.path, "nothing was computed or written") from None

    def _abandon(self, fd: int, flocked: bool) -> None:
        """Give up a lock file we hold but could not write our record into."""
        try:
            if flocked and _inode(self.path) == os.fstat(fd).st_ino:
                os.unlink(self.path)
        except OSError:
            pass
        finally:
            os.close(fd)

    def _flock(self, fd: int) -> bool:
        """Exclusive flock: True if taken, False where the file system has none; raises if held."""
        if fcntl is None:
            return False
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            raise OutputInUseError(self._in_use(_holder(fd))) from None
        except OSError as e:
            if e.errno in _NO_FLOCK:
                return False
            raise

    def _take(self, fd: int, flocked: bool) -> None:
        """Check what the lock file records, then write our own record into it."""
        info = _read_info(fd)
        if info is not None or os.fstat(fd).st_size:
            reason = self._stale_reason(info, os.fstat(fd).st_mtime, flocked)
            if reason is None:
                raise OutputInUseError(self._in_use(info or {}))
            held = f"lock of {_describe(info)}" if info else "lock (its record is unreadable)"
            warnings.warn(f"{self.out}: taking over a stale {held}: {reason}", StaleLockWarning, stacklevel=2)
        record = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "started": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "proc_start": _proc_start(os.getpid()),
        }
        data = json.dumps(record).encode()
        os.ftruncate(fd, 0)
        os.pwrite(fd, data, 0)
        os.fsync(fd)

    def _stale_reason(self, info: dict | None, mtime: float, flocked: bool) -> str | None:
        """Why the recorded holder is gone, or None while it may still be running."""
        age = time.time() - mtime
        host = (info or {}).get("host")
        if host and host != socket.gethostname():  # flock may not reach across hosts: trust the heartbeat
            if age > self.stale_after:
                return f"not refreshed for {age / 60:.0f} min (stale after {self.stale_after / 60:g} min)"
            return None
        if flocked:  # the kernel released its flock: the holder has exited
            pid = (info or {}).get("pid")
            return f"PID {pid} is no longer running" if pid and not _alive(pid, None) else "its process has exited"
        if info is None:
            return "unreadable" if age > self.stale_after else None
        return None if _alive(info.get("pid"), info.get("proc_start")) else f"PID {info.get('pid')} is no longer running"

    def _in_use(self, info: dict) -> str:
        who = _describe(info) if info.get("pid") else "another run (starting)"
        if info.get("host") and info["host"] != socket.gethostname():
            hint = f"; it counts as stale {self.stale_after / 60:g} min after its last refresh"
        else:
            hint = ""
        return f"{self.out} is in use by {who}; wait for it to finish or stop it (lock file {self.path}{hint})"

    # -- hold and release ---------------------------------------------------------
    def _start_heartbeat(self) -> None:
        """Touch the lock every HEARTBEAT s, so that other hosts see it alive."""

        fd, self._stop = self._fd, threading.Event()

        def beat() -> None:
            while not self._stop.wait(HEARTBEAT):
                try:
                    os.utime(fd)
                except OSError:
                    return

        self._beat = threading.Thread(target=beat, name=f"lock {self.path.name}", daemon=True)
        self._beat.start()

    def release(self) -> None:
        """Remove the lock file (if it is still ours) and drop the flock."""
        if self._fd is None:
            return
        self._stop.set()
        if self._beat is not None:
            self._beat.join()  # it wakes at once; then fd cannot be touched after it is closed
        try:
            if _inode(self.path) == os.fstat(self._fd).st_ino:
                os.unlink(self.path)  # before unlocking: a waiting run then opens a new file
        except OSError:
            pass
        finally:
            os.close(self._fd)
            self._fd = None

    def __enter__(self) -> "SweepLock":
        self.acquire()
        return self

    def __exit__(self, *exc) -> None:
        self.release()


def _inode(path: Path) -> int | None:
    try:
        return os.stat(path).st_ino
    except OSError:
        return None


def _holder(fd: int) -> dict:
    """The record of the run that holds the flock; one that just took over a stale lock gets a moment to write its own."""
    info = _read_info(fd, wait=True) or {}
    for _ in range(25):
        if info.get("host") != socket.gethostname() or _alive(info.get("pid"), info.get("proc_start")):
            break
        time.sleep(0.02)
        info = _read_info(fd) or info
    return info


def _read_info(fd: int, wait: bool = False) -> dict | None:
    """The holder's record; ``wait``: give a holder that just took the lock a moment to write it."""
    for _ in range(20 if wait else 1):
        try:
            info = json.loads(os.pread(fd, 4096, 0).decode())
            if isinstance(info, dict):
                return info
        except (OSError, ValueError):
            pass
        if wait:
            time.sleep(0.02)
    return None
