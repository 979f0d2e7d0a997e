"""Executors for campaigns of independent runs (planner suites, exploration sweeps).

:func:`executor` yields a :class:`concurrent.futures.Executor`: the executor of a Dask ``distributed``
cluster when an address is given (``Client(address).get_executor()``), otherwise a local
:class:`IsolatedPool`. Callers submit picklable functions and read futures, whichever it is.

:class:`IsolatedPool` is a process pool for runs that may misbehave: ``workers`` processes, each reused for
many runs (start-up is paid once per process, not per run), where

* a run that exceeds ``hard_timeout`` seconds of wall-clock time has its worker killed and its future fails
  with :class:`RunKilled` (the run's own limits should stop it first: this is the backstop);
* a worker that dies (a crash, a signal, the kernel's out-of-memory killer) fails only the future of the
  run it was doing, with :class:`WorkerDied`; a fresh worker takes its place;
* ``memory_mb`` caps each worker's address space (``RLIMIT_AS``), so a run that allocates too much gets a
  ``MemoryError`` in its own process instead of taking the machine down.

:class:`concurrent.futures.ProcessPoolExecutor` does none of this: one dead worker breaks the whole pool.
Workers are started with ``spawn`` (no fork of a threaded parent).

:func:`actors` yields *stateful* workers for one computation split across processes (the parallel search of
one task): N objects of a class, each in its own spawned process or as an actor of a Dask cluster, called by
method name; a call returns at once and its reply is read later, so the caller can keep working meanwhile.
"""

from __future__ import annotations

import os
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator
from concurrent.futures import Executor, Future
from contextlib import contextmanager
from typing import Any

from delkit.errors import DelkitError

__all__ = ["IsolatedPool", "RunKilled", "RunInterrupted", "WorkerDied", "executor", "actors", "Actor",
           "parse_scheduler"]


class RunKilled(RuntimeError):
    """A run exceeded the pool's hard wall-clock limit; its worker was killed."""


class RunInterrupted(RuntimeError):
    """The pool was terminated (:meth:`IsolatedPool.terminate`: the batch was interrupted) while the run was
    waiting or running; its worker was killed."""


class WorkerDied(RuntimeError):
    """The worker process died while doing the run (crash, signal, out-of-memory kill)."""


def _tie_to_parent() -> None:
    """In a worker: die with the parent (Linux ``PR_SET_PDEATHSIG``: SIGKILL when the parent ends, however it
    ends, so no worker outlives its batch), and leave SIGINT to the parent (a Ctrl-C reaches the whole process
    group; the parent decides what the interrupted batch reports and ends the workers itself)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):  # pragma: no cover - not Linux: the pipe's end of file still ends an idle worker
        pass
    if os.getppid() == 1:  # the parent ended before the line above ran
        os._exit(1)


def _worker(conn: Any, memory_mb: float | None) -> None:
    """Worker loop: receive (fn, args, kwargs), send back (True, result, cpu) or (False, exception, cpu)."""
    import pickle
    import resource

    _tie_to_parent()
    _CURRENT[:] = [conn]
    if memory_mb:
        limit = int(memory_mb * 2**20)
        _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        if hard == resource.RLIM_INFINITY or limit <= hard:
            resource.setrlimit(resource.RLIMIT_AS, (limit, hard))
    for fn, args, kwargs in _requests(conn):
        t0 = time.process_time()
        try:
            out: tuple = (True, fn(*args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 - every failure goes back to the parent's future
            out = (False, exc)
        cpu = time.process_time() - t0
        try:
            with _SEND_LOCK:
                conn.send((*out, cpu))
        except (pickle.PicklingError, TypeError, AttributeError) as exc:  # an unpicklable result or exception
            conn.send((False, RuntimeError(f"{type(out[1]).__name__}: {out[1]} (not picklable: {exc})"), cpu))


_CURRENT: list = []  # in a pool worker: the connection to the parent (for :func:`answer_and_exit`)
_SEND_LOCK = threading.Lock()


def answer_and_exit(value: Any, cpu: float = 0.0) -> None:
    """In a pool worker, from any thread: send ``value`` as the current run's result and end the worker at once
    (``os._exit``) — for a watchdog whose run is stuck in native code past its limit: the run is answered (e.g.
    with a limit record and the counters so far) and the pool replaces the worker. Outside a worker: no-op."""
    if not _CURRENT:
        return
    try:
        with _SEND_LOCK:
            _CURRENT[0].send((True, value, cpu))
    finally:
        os._exit(0)


def _requests(conn: Any) -> Iterator[Any]:
    """The requests a worker or actor process receives on ``conn``, until None (the parent's stop) or end of
    file (the parent has gone)."""
    while True:
        try:
            job = conn.recv()
        except (EOFError, OSError):
            return
        if job is None:
            return
        yield job


class _Slot:
    __slots__ = ("proc", "conn", "job", "started")

    def __init__(self, proc: Any, conn: Any) -> None:
        self.proc, self.conn = proc, conn
        self.job: tuple[Future, Any] | None = None
        self.started = 0.0


class IsolatedPool(Executor):
    """A process pool where one run's crash, hang or memory blow-up fails that run only (module docstring).

    ``cpu`` of every finished run (its worker's CPU seconds) is recorded in ``future.cpu``.
    """

    def __init__(self, workers: int | None = None, *, hard_timeout: float | None = None,
                 memory_mb: float | None = None) -> None:
        import multiprocessing

        self._ctx = multiprocessing.get_context("spawn")
        self.workers = max(1, int(workers or os.cpu_count() or 1))
        self.hard_timeout = hard_timeout
        self.memory_mb = memory_mb
        self._queue: deque[tuple[Future, tuple]] = deque()
        self._slots: list[_Slot] = []
        self._lock = threading.Lock()
        self._wake_r, self._wake_w = self._ctx.Pipe(duplex=False)
        self._shutdown = False
        self._terminate = False
        self._thread = threading.Thread(target=self._loop, name="IsolatedPool", daemon=True)
        self._thread.start()

    # ------------------------------------------------------------------ Executor
    def submit(self, fn: Callable, /, *args: Any, **kwargs: Any) -> Future:
        if self._shutdown:
            raise RuntimeError("cannot submit to a pool that is shut down")
        fut: Future = Future()
        with self._lock:
            self._queue.append((fut, (fn, args, kwargs)))
        self._wake()
        return fut

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        if cancel_futures:
            with self._lock:
                while self._queue:
                    self._queue.popleft()[0].cancel()
        self._shutdown = True
        self._wake()
        if wait:
            self._thread.join()

    def terminate(self, reason: str = "interrupted") -> None:
        """End now: every waiting run is cancelled, every running one fails with :class:`RunInterrupted` and
        its worker is killed (SIGKILL); returns when the workers are gone."""
        with self._lock:
            while self._queue:
                self._queue.popleft()[0].cancel()
        self._reason = reason
        self._terminate = self._shutdown = True
        self._wake()
        self._thread.join(10.0)

    # ------------------------------------------------------------------ internals
    def _wake(self) -> None:
        try:
            self._wake_w.send_bytes(b"x")
        except OSError:  # pragma: no cover - the loop has ended
            pass

    def _spawn(self) -> _Slot:
        parent, child = self._ctx.Pipe()
        proc = self._ctx.Process(target=_worker, args=(child, self.memory_mb), daemon=True)
        proc.start()
        child.close()
        return _Slot(proc, parent)

    def _fail(self, slot: _Slot, exc: BaseException) -> None:
        fut, _ = slot.job  # type: ignore[misc]
        slot.job = None
        if not fut.done():
            fut.set_exception(exc)

    def _replace(self, slot: _Slot) -> None:
        try:
            slot.conn.close()
        except OSError:  # pragma: no cover
            pass
        if slot.proc.is_alive():
            slot.proc.kill()
        slot.proc.join(1.0)
        self._slots.remove(slot)

    def _dispatch(self) -> None:
        with self._lock:
            for slot in [s for s in self._slots if s.job is None and not s.proc.is_alive()]:
                self._replace(slot)  # a worker that answered and ended (executors.answer_and_exit)
            while self._queue:
                idle = next((s for s in self._slots if s.job is None), None)
                if idle is None:
                    if len(self._slots) >= self.workers:
                        return
                    idle = self._spawn()
                    self._slots.append(idle)
                fut, job = self._queue.popleft()
                if not fut.set_running_or_notify_cancel():
                    continue
                idle.job, idle.started = (fut, job), time.monotonic()
                idle.conn.send(job)

    def _loop(self) -> None:
        from multiprocessing.connection import wait

        while True:
            if self._terminate:
                for slot in list(self._slots):
                    if slot.job is not None:
                        self._fail(slot, RunInterrupted(getattr(self, "_reason", "interrupted")))
                    if slot.proc.is_alive():
                        slot.proc.kill()
                for slot in list(self._slots):
                    self._replace(slot)
                return
            self._dispatch()
            busy = [s for s in self._slots if s.job is not None]
            if self._shutdown and not busy and not self._queue:
                break
            ready = wait([self._wake_r] + [s.conn for s in busy] + [s.proc.sentinel for s in busy], timeout=0.1)
            if self._wake_r in ready:
                while self._wake_r.poll():
                    self._wake_r.recv_bytes()
            now = time.monotonic()
            for slot in busy:
                if slot.conn in ready:
                    try:
                        ok, value, cpu = slot.conn.recv()
                    except (EOFError, OSError):
                        code = slot.proc.exitcode if slot.proc.join(1.0) is None else None
                        self._fail(slot, WorkerDied(_died(code)))
                        self._replace(slot)
                        continue
                    fut, _ = slot.job  # type: ignore[misc]
                    slot.job = None
                    fut.cpu = cpu  # type: ignore[attr-defined]
                    if not fut.done():
                        fut.set_result(value) if ok else fut.set_exception(value)
                elif slot.proc.sentinel in ready:
                    slot.proc.join(1.0)
                    self._fail(slot, WorkerDied(_died(slot.proc.exitcode)))
                    self._replace(slot)
                elif self.hard_timeout is not None and now - slot.started > self.hard_timeout:
                    self._fail(slot, RunKilled(f"killed after {now - slot.started:.1f} s of wall-clock time (the "
                                               f"pool's hard limit is {self.hard_timeout:g} s)"))
                    self._replace(slot)
        for slot in list(self._slots):
            try:
                slot.conn.send(None)
            except OSError:
                pass
            slot.proc.join(2.0)
            self._replace(slot)


def _died(code: int | None) -> str:
    if code is not None and code < 0:
        import signal

        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        why = " (the kernel's out-of-memory killer sends SIGKILL)" if name == "SIGKILL" else ""
        return f"the worker process was killed by {name}{why}"
    return f"the worker process exited with status {code}"


#: the address schemes ``--scheduler`` takes (TLS needs a security configuration that delkit does not take)
SCHEMES = ("tcp",)


def parse_scheduler(address: str | None, option: str = "--scheduler",
                    error: type[DelkitError] = DelkitError) -> tuple[str, int] | None:
    """(host, port) of a Dask scheduler address ``[tcp://]HOST:PORT`` (HOST a name, an IPv4 address or an
    IPv6 address in brackets; PORT 1..65535), or None for None; anything else raises ``error`` with one line
    saying what is wrong and how to write it. Nothing is contacted."""
    import re

    if address is None:
        return None
    fix = f"write {option} tcp://HOST:PORT, e.g. {option} tcp://127.0.0.1:8786 (or leave it out: local processes)"
    text = address.strip()
    if not text:
        raise error(f"{option} is empty; {fix}")
    scheme, sep, rest = text.partition("://")
    if not sep:
        scheme, rest = "tcp", text
    scheme = scheme.lower()
    if scheme in ("tls", "wss"):
        raise error(f"{option} {address!r}: {scheme}:// needs a TLS security configuration, which delkit does not "
                    f"take; use a tcp:// address (e.g. through an SSH tunnel: tcp://127.0.0.1:8786)")
    if scheme not in SCHEMES:
        raise error(f"{option} {address!r}: unknown scheme {scheme!r}; {fix}")
    m = re.fullmatch(r"(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):([0-9]{1,20})/?", rest)
    if m is None:
        raise error(f"{option} {address!r}: not HOST:PORT; {fix}")
    host, port = m.group(1), int(m.group(2))
    if not 1 <= port <= 65535:
        raise error(f"{option} {address!r}: port {m.group(2)} is out of range 1..65535; {fix}")
    if len(host) > 253:
        raise error(f"{option} {address!r}: the host name is longer than 253 characters; {fix}")
    return host.strip("[]"), port


def _reachable(host: str, port: int, timeout: float, address: str, option: str,
               error: type[DelkitError]) -> None:
    """Refuse (``error``) a scheduler address where nothing accepts a TCP connection within ``timeout`` s —
    before Dask's client, whose own failures on such addresses are not one line."""
    import socket

    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except (OSError, OverflowError, ValueError, UnicodeError) as exc:
        why = "timed out" if isinstance(exc, TimeoutError) else (getattr(exc, "strerror", None) or str(exc))
        raise error(f"cannot reach the Dask scheduler at {address!r} ({why}); start one with 'dask scheduler' "
                    f"or leave {option} out to use local processes") from None


def _dask_client(address: str, timeout: float, option: str = "--scheduler",
                 error: type[DelkitError] = DelkitError) -> Any:
    """A ``distributed.Client`` of the scheduler at ``address``; else ``error`` saying how to fix it
    (``option`` names the command's option in the message)."""
    inproc = address.strip().lower().startswith("inproc://")  # a cluster inside this very process (the API's
    # LocalCluster(processes=False)): nothing on the network to parse or probe
    host, port = (None, None) if inproc else parse_scheduler(address, option, error)  # type: ignore[misc]
    try:
        from distributed import Client
    except ImportError as exc:  # pragma: no cover - dask is a declared extra
        raise error(f"{option} needs the 'distributed' package (pip install 'delkit[dask]')") from exc
    if not inproc:
        _reachable(host, port, min(timeout, 5.0), address, option, error)  # type: ignore[arg-type]
    try:
        return Client(address if "://" in address else f"tcp://{address.strip()}", timeout=timeout)
    except Exception as exc:  # noqa: BLE001 - unreachable, timed out, refused, not a scheduler: one line
        raise error(f"cannot reach the Dask scheduler at {address!r} ({type(exc).__name__}: {exc}); start one "
                    f"with 'dask scheduler' or leave {option} out to use local processes") from None


@contextmanager
def dask_executor(address: str, timeout: float = 10.0, *, option: str = "--scheduler",
                  error: type[DelkitError] = DelkitError) -> Iterator[Executor]:
    """The executor of the Dask cluster at ``address`` (e.g. ``tcp://127.0.0.1:8786``), closed afterwards;
    ``option`` names the command's option in the messages, ``error`` is the exception they are raised as."""
    client = _dask_client(address, timeout, option, error)
    try:
        yield client.get_executor()
    finally:
        client.close()


@contextmanager
def executor(workers: int | None = None, dask: str | None = None, dask_timeout: float = 10.0, *,
             hard_timeout: float | None = None, memory_mb: float | None = None) -> Iterator[Executor]:
    """A local :class:`IsolatedPool`, or the executor of the Dask cluster at ``dask`` (e.g.
    ``tcp://127.0.0.1:8786``; its workers and their memory limits are the cluster's)."""
    if dask:
        with dask_executor(dask, dask_timeout) as ex:
            yield ex
    else:
        pool = IsolatedPool(workers, hard_timeout=hard_timeout, memory_mb=memory_mb)
        try:
            yield pool
        finally:
            pool.shutdown(wait=True, cancel_futures=True)


# ---------------------------------------------------------------------------------------------- actors
def _actor_main(conn: Any, cls: Callable, args: tuple) -> None:
    """An actor's process: build ``cls(*args)`` (lazily: its failure is the first call's reply), then answer
    (method, args) requests with (True, result) or (False, exception) until None or end of file."""
    import gc

    _tie_to_parent()
    gc.disable()  # the actors of a search keep many long-lived objects and make no reference cycles per call
    obj: Any = None
    for name, cargs in _requests(conn):
        try:
            if obj is None:
                obj = cls(*args)
            out: tuple = (True, getattr(obj, name)(*cargs))
        except BaseException as exc:  # noqa: BLE001 - the failure is the caller's to report
            out = (False, exc)
        try:
            conn.send(out)
        except OSError:  # the caller has gone (it stopped at a limit and exited): nobody to answer
            return


class _Reply:
    __slots__ = ("_conn", "_proc", "_pending")

    def __init__(self, conn: Any, proc: Any, pending: list) -> None:
        self._conn, self._proc, self._pending = conn, proc, pending

    def result(self, timeout: float | None = None) -> Any:
        """The call's value (or its exception); :class:`TimeoutError` if none came within ``timeout`` s."""
        try:
            if timeout is not None and not self._conn.poll(max(0.0, timeout)):
                raise TimeoutError(f"no reply within {timeout:g} s")
            ok, value = self._conn.recv()
        except (EOFError, OSError):
            self._proc.join(1.0)
            raise WorkerDied(_died(self._proc.exitcode)) from None
        self._pending[0] = False
        if not ok:
            raise value
        return value


class Actor:
    """A stateful worker: ``call(method, *args)`` starts ``obj.method(*args)`` in the worker and returns an
    object whose ``result(timeout=None)`` waits for the reply (raising the worker's exception,
    :class:`WorkerDied`, or :class:`TimeoutError`). One call at a time per actor: read a reply before the
    next call."""

    def __init__(self, call: Callable[..., Any], close: Callable[[], None]) -> None:
        self.call, self.close = call, close


def _local_actor(ctx: Any, cls: Callable, args: tuple) -> Actor:
    parent, child = ctx.Pipe()
    proc = ctx.Process(target=_actor_main, args=(child, cls, args), daemon=True)
    proc.start()
    child.close()

    pending = [False]  # a call whose reply was not read: the actor is (or may be) still working

    def call(name: str, *cargs: Any) -> _Reply:
        parent.send((name, cargs))
        pending[0] = True
        return _Reply(parent, proc, pending)

    def close() -> None:
        try:
            parent.send(None)
        except OSError:
            pass
        # an idle actor ends by itself; it is killed if it is busy (a limit) or slow to free its memory (a search
        # leaves millions of objects: ~1 s of deallocation that nothing needs)
        proc.join(0.0 if pending[0] else 0.05)
        if proc.is_alive():
            proc.kill()
            proc.join(1.0)
        parent.close()

    return Actor(call, close)


@contextmanager
def actors(cls: Callable, inits: list[tuple], dask: str | None = None,
           dask_timeout: float = 10.0) -> Iterator[list[Actor]]:
    """One :class:`Actor` per argument tuple of ``inits`` (``cls(*args)``): each in its own spawned local
    process, or an actor of the Dask cluster at ``dask`` (spread over its workers in turn; the class must be
    importable there). Closed (processes ended) on exit."""
    if dask:
        client = _dask_client(dask, dask_timeout)
        try:
            workers = sorted(client.scheduler_info().get("workers", {})) or [None]
            futs = [client.submit(cls, *args, actor=True, pure=False,
                                  workers=None if workers[i % len(workers)] is None else [workers[i % len(workers)]])
                    for i, args in enumerate(inits)]
            out = []
            for fut in futs:
                proxy = fut.result()
                out.append(Actor(lambda name, *a, _p=proxy: getattr(_p, name)(*a), lambda: None))
            yield out
        finally:
            client.close()
        return
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    made: list[Actor] = []
    try:
        for args in inits:
            made.append(_local_actor(ctx, cls, args))
        yield made
    finally:
        for a in made:
            a.close()
