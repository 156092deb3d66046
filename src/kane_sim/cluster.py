"""Sweeps on a Dask distributed cluster (python3-distributed): the cases cut into chunks, each
chunk one kane_sim._core.sweep call on a worker (C++, the GIL released, SIMD lanes where the
cases allow), gathered in case order. The workers import the same kane_sim (start them after
sourcing the same build's setup.bash). A worker lost mid-sweep loses nothing: the scheduler
runs its chunks again elsewhere. doc/guide/cluster.md says how to start a cluster.
"""
import os
import sys
import uuid

import numpy as np

from kane_sim import _core

CONNECT_TIMEOUT = 10.0  # [s] to reach a scheduler before saying it cannot be reached
LOST = ("the sweep's tasks were lost on the cluster: the scheduler gone, or another client "
        "cancelled them (%s)")


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during a cluster sweep: the cluster's tasks are cancelled; `chunks` holds each
    chunk's result, None where it had not finished."""

    def __init__(self, chunks):
        super().__init__("sweep interrupted: the cluster's tasks were cancelled")
        self.chunks = chunks


class Failed(RuntimeError):
    """The cluster failed mid-sweep (the scheduler lost, a worker that cannot import kane_sim):
    the message says what; `chunks` holds the finished chunks' results (None elsewhere)."""

    def __init__(self, message, chunks):
        super().__init__(message)
        self.chunks = chunks


def _why(error):
    """A cluster's failure in one sentence."""
    if isinstance(error, ImportError):
        return ("a worker cannot import %s (%s): start every worker after sourcing this build's "
                "devel/setup.bash (doc/guide/cluster.md)" % (getattr(error, "name", "kane_sim")
                                                              or "kane_sim", error))
    text = str(error).splitlines()[0] if str(error) else ""
    return LOST % ("%s%s" % (type(error).__name__, ": " + text[:200] if text else ""))


def run_chunk(config_yaml, keys, rows, first_case, duration, torque, simd, vector_trig):
    """One chunk on a worker: its cases' columns (as kane_sim.sweep) and their CSV rows, numbered
    from first_case, as `simulate --sweep` writes them ("csv_rows")."""
    config = _core.Config.from_yaml(config_yaml)  # the worker's own loader, as the client's
    out = _core.sweep(config, list(keys), [list(r) for r in rows], float(duration), torque,
                      1, simd, bool(vector_trig), int(first_case))
    return {k: (v if k == "csv_rows" else np.asarray(v)) for k, v in out.items()}


def connect(scheduler, timeout=None):
    """A distributed.Client of the scheduler at `scheduler` ("tcp://HOST:PORT", or a
    scheduler file's path: .json), tried for `timeout` seconds (default CONNECT_TIMEOUT);
    ValueError naming the address when it cannot be reached."""
    timeout = CONNECT_TIMEOUT if timeout is None else timeout
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("a cluster sweep needs Dask distributed (apt install "
                         "python3-distributed)") from None
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise ValueError("scheduler: give tcp://HOST:PORT or a scheduler file, got %r"
                         % (scheduler,))
    if scheduler.endswith(".json"):
        if not os.path.isfile(scheduler):
            raise ValueError("scheduler file %s does not exist (dask scheduler "
                             "--scheduler-file writes it)" % scheduler)
        kwargs = {"scheduler_file": scheduler}
    else:
        kwargs = {"address": scheduler}
    try:
        return Client(timeout=timeout, **kwargs)
    except KeyboardInterrupt:
        raise
    except Exception as e:  # Dask raises OSError, TimeoutError, ValueError, TypeError, ...
        text = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise ValueError("scheduler %s cannot be reached (%s): is `dask scheduler` running "
                         "there, and the port open?" % (scheduler, text[:300])) from None


def client_of(client):
    """`client` checked: a running distributed.Client (ValueError, TypeError otherwise)."""
    from distributed import Client
    if not isinstance(client, Client):
        raise TypeError("client must be a distributed.Client or a scheduler's address, got %r"
                        % (client,))
    if client.status != "running":
        raise ValueError("client: the distributed.Client is %s (a closed Client sends nothing)"
                         % client.status)
    return client


def run(client, config_yaml, keys, rows, duration, torque, simd="auto", vector_trig=False,
        chunk=64, on_chunk=None):
    """Every chunk of `rows` on the cluster of `client`: a list of run_chunk's results in case
    order. on_chunk(index, result) is called as each finishes (any order). Ctrl-C (or any
    exception while waiting) cancels the tasks; KeyboardInterrupt becomes Interrupted, with the
    finished chunks."""
    from distributed import as_completed
    tag = uuid.uuid4().hex[:8]
    starts = list(range(0, len(rows), chunk))
    futures = [client.submit(run_chunk, config_yaml, keys, rows[s:s + chunk], s, duration,
                             torque, simd, vector_trig, key="kane_sim-sweep-%s-%d" % (tag, s),
                             pure=False)
               for s in starts]
    index = {f.key: i for i, f in enumerate(futures)}
    chunks = [None] * len(futures)
    if not client.scheduler_info().get("workers"):
        print("sweep: the scheduler has no workers yet: waiting for them (Ctrl-C stops)",
              file=sys.stderr)
    try:
        for future in as_completed(futures):
            i = index[future.key]
            if future.status == "cancelled":
                raise Failed(LOST % "cancelled", chunks)
            if future.status != "finished":
                raise future.exception()
            result = future.result()
            chunks[i] = result
            if on_chunk:
                on_chunk(i, result)
    except KeyboardInterrupt:
        _cancel(client, futures)
        raise Interrupted(chunks) from None
    except Failed:
        _cancel(client, futures)
        raise
    except Exception as e:
        _cancel(client, futures)
        raise Failed(_why(e), chunks) from None
    return chunks


def _cancel(client, futures):
    """Cancels the sweep's tasks if the scheduler is still there to hear it."""
    try:
        client.cancel(futures)
    except Exception:  # the scheduler is gone: nothing runs for this sweep any more
        pass


def join(keys, rows, chunks, chunk):
    """The chunks' columns as one kane_sim.sweep dict; an unfinished chunk's cases are
    'interrupted' with NaN results (as a local sweep's after Ctrl-C)."""
    columns = None
    for c in chunks:
        if c is not None:
            columns = [k for k in c if k != "csv_rows"]
            break
    if columns is None:
        return None
    parts = []
    for i, c in enumerate(chunks):
        if c is not None:
            parts.append(c)
            continue
        n = len(rows[i * chunk:(i + 1) * chunk])
        filler = {k: np.full(n, np.nan) for k in columns}
        for k, key in enumerate(keys):
            filler[key] = np.array([r[k] for r in rows[i * chunk:(i + 1) * chunk]], dtype=float)
        filler["status"] = np.array(["interrupted"] * n)
        filler["error"] = np.array([""] * n)
        parts.append(filler)
    return {k: np.concatenate([np.asarray(p[k]) for p in parts]) for k in columns}


def sweep(config, keys, rows, duration, profile, simd, vector_trig, client, chunk):
    """kane_sim.sweep's cases on a cluster: config a loaded _core.Config, client a Client or a
    scheduler's address. A cluster that fails mid-sweep raises Failed (a RuntimeError), Ctrl-C
    Interrupted, each with the finished cases in `.result`. Needs nothing of kane_sim but _core
    (kane_sim.core imports this module, never the other way round)."""
    if not rows:  # nothing to send: the local sweep's empty columns
        return {k: np.asarray(v) for k, v in _core.sweep(
            config, list(keys), [], float(duration), profile, 1, simd,
            bool(vector_trig)).items()}
    own = isinstance(client, str)
    client = connect(client) if own else client_of(client)
    try:
        chunks = run(client, config.yaml(), list(keys), rows, float(duration), profile, simd,
                     bool(vector_trig), int(chunk))
    except (Interrupted, Failed) as stopped:
        stopped.result = join(list(keys), rows, stopped.chunks, int(chunk))
        raise
    finally:
        if own:
            client.close()
    return join(list(keys), rows, chunks, int(chunk))
