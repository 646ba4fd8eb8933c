"""Mining across many machines on Ray: one task per log, one submission gathered.

``scenalog.ray.mine(rules, log_dirs, ...)`` runs one Ray task per log: the task mines every
program on its log with ``scenalog.mine`` (so the log is read, and its facts extracted, once for
all the programs), and the driver gathers the per-log predictions into one submission: the
official pickle byte for byte what a single ``scenalog.mine`` over the same logs writes, and the
same Arrow table.

- Programs are read on the driver and shipped to the tasks as text: only the logs must be
  readable by the workers, at the same paths (shared storage, or the same copy on every node).
- A task that fails (its worker died, its node was lost, an ``OSError`` such as a flaky network
  file system) is retried up to ``max_retries`` times by Ray; a log whose task still fails is
  listed in ``failures`` with its pairs absent, as a log that cannot be read is in a single
  run. Each log is gathered exactly once and each of its (log, program) pairs checked present
  once, so the submission has no duplicate or missing pair.

On a real cluster, start Ray on the machines (``ray start --head`` on one,
``ray start --address=HEAD:6379`` on the others), install this package on every node, then
either call ``ray.init(address="auto")`` (on a node) / ``ray.init("ray://HEAD:10001")`` (from
outside) before ``scenalog.ray.mine``, or set ``RAY_ADDRESS``; without a running Ray,
``scenalog.ray.mine`` starts a local one (``ray.init()``).
"""

from __future__ import annotations

import json
import os
import tempfile
from typing import Any, Dict, Iterable, List, Optional, Union

import pyarrow as pa

import scenalog
from . import _native

__all__ = ["mine"]

# Test-only fault injection: with this set to a directory, each log's first attempt kills its
# worker process (after leaving a marker file there), so the tests can watch Ray retry it.
_CRASH_ONCE_ENV = "SCENALOG_RAY_TEST_CRASH_ONCE_DIR"


def _mine_one_log(programs: List[tuple], log_dir: str, log_id: str, options: Dict[str, Any]) -> dict:
    """The task: every program on one log, in a private temporary directory."""
    crash_dir = os.environ.get(_CRASH_ONCE_ENV)
    if crash_dir:
        marker = os.path.join(crash_dir, log_id)
        if not os.path.exists(marker):
            open(marker, "w").close()
            os._exit(1)
    with tempfile.TemporaryDirectory(prefix="scenalog-ray-") as tmp:
        rules_dir = os.path.join(tmp, "rules")
        os.mkdir(rules_dir)
        paths = []
        for name, text in programs:
            path = os.path.join(rules_dir, name)
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
            paths.append(path)
        result = scenalog.mine(paths, [log_dir], **options)
    return {
        "log_id": log_id,
        "submission": result.submission,
        "predictions": result.predictions,
        "matches": result.matches,
        "pairs": result.pairs,
        "failures": result.failures,
    }


def _read_programs(rules) -> List[tuple]:
    files = _native.rule_files([os.fspath(r) for r in scenalog._paths("rules", rules)])
    names = [os.path.basename(f) for f in files]
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise scenalog.ScenalogError(
            f"rules: two programs share the file name {dup[0]!r}; a distributed run keys programs by file name"
        )
    programs = []
    for f in files:
        try:
            with open(f, encoding="utf-8") as fh:
                programs.append((f, os.path.basename(f), fh.read()))
        except OSError as e:
            raise scenalog.ScenalogError(f"cannot read `{f}`: {e}") from e
    return programs


def mine(
    rules,
    log_dirs,
    *,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    threads_per_task: int = 1,
    num_cpus_per_task: Optional[float] = None,
    max_retries: int = 3,
    max_tuples: Optional[int] = None,
    timeout_ms: Optional[int] = None,
    ray_remote_args: Optional[Dict[str, Any]] = None,
) -> "scenalog.MineResult":
    """Mines ``rules`` (``.dl`` files or directories) over ``log_dirs`` (log directories or
    directories of logs) on a Ray cluster, one task per log, and gathers one submission.

    Returns a ``scenalog.MineResult`` as ``scenalog.mine`` does (``predictions`` table,
    ``submission`` pickle bytes, ``matches``, ``pairs``, ``failures``); with ``out`` it also
    writes ``predictions.pkl``, ``predictions.feather`` and ``matches.json`` there.
    ``threads_per_task`` threads mine each log (and the task asks Ray for as many CPUs unless
    ``num_cpus_per_task`` says otherwise); ``max_retries`` is Ray's retry count for a failed
    task; ``max_tuples`` and ``timeout_ms`` are per pair as in ``scenalog mine``;
    ``ray_remote_args`` go to ``.options()`` of every task (e.g. ``{"memory": 4 << 30}``).
    """
    import ray

    # Programs that do not check are listed and left out, as in a single run.
    program_failures: List[str] = []
    programs = []
    for path, name, text in _read_programs(rules):
        errors = [d for d in scenalog.check(text) if d.get("severity") == "error"]
        if errors:
            d = errors[0]
            program_failures.append(f"`{path}`:{d.get('line')}:{d.get('column')}: {d.get('message')}")
        else:
            programs.append((name, text))
    if not programs:
        raise scenalog.ScenalogError("\n  ".join(["no program to mine", *program_failures]))
    logs, log_problems = _native.log_dirs([os.fspath(p) for p in scenalog._paths("log_dirs", log_dirs)])
    if not logs:
        raise scenalog.ScenalogError("no log to mine")
    if not ray.is_initialized():
        ray.init()

    options: Dict[str, Any] = {"threads": threads_per_task}
    if max_tuples is not None:
        options["max_tuples"] = max_tuples
    if timeout_ms is not None:
        options["timeout_ms"] = timeout_ms
    remote_args = {
        "num_cpus": threads_per_task if num_cpus_per_task is None else num_cpus_per_task,
        "max_retries": max_retries,
        "retry_exceptions": [OSError],
    }
    remote_args.update(ray_remote_args or {})
    task = ray.remote(_mine_one_log).options(**remote_args)
    programs_ref = ray.put(programs)
    pending = {task.remote(programs_ref, d, log_id, options): log_id for d, log_id in logs}

    results: Dict[str, dict] = {}
    failures: List[str] = program_failures + list(log_problems)
    while pending:
        done, _ = ray.wait(list(pending), num_returns=1)
        for ref in done:
            log_id = pending.pop(ref)
            try:
                part = ray.get(ref)
            except Exception as e:  # the task failed after its retries
                failures.append(f"log {log_id}: its task failed after {max_retries} retries: {e}")
                continue
            if part["log_id"] != log_id or log_id in results:
                raise scenalog.ScenalogError(f"log {log_id}: gathered twice or under another id")
            results[log_id] = part
    return _gather(programs, results, failures, out)


def _gather(programs: List[tuple], results: Dict[str, dict], failures: List[str], out) -> "scenalog.MineResult":
    """One submission from the per-log parts, in log-id order, each pair checked present once."""
    names = sorted(os.path.splitext(n)[0] for n, _ in programs)
    order = sorted(results)
    pairs: List[dict] = []
    for log_id in order:
        part = results[log_id]
        got = sorted(p["program"] for p in part["pairs"])
        if got != names or any(p["log_id"] != log_id for p in part["pairs"]):
            raise scenalog.ScenalogError(
                f"log {log_id}: the task mined the programs {got}, expected each of {names} once"
            )
        pairs.extend(part["pairs"])
        failures.extend(part["failures"])
    submission = _native.join_pickles([results[l]["submission"] for l in order])
    tables = [results[l]["predictions"] for l in order]
    if not tables:
        raise scenalog.ScenalogError("\n  ".join(["no log was mined", *failures]))
    # Each log's table has its own dictionaries (its log id): one dictionary per column, as an
    # Arrow IPC file needs.
    predictions = pa.concat_tables(tables).unify_dictionaries()
    matches = [m for l in order for m in results[l]["matches"]]
    if out is not None:
        out_dir = os.fspath(out)
        os.makedirs(out_dir, exist_ok=True)
        _write_atomic(os.path.join(out_dir, "predictions.pkl"), submission)
        sink = pa.BufferOutputStream()
        options = pa.ipc.IpcWriteOptions(compression="zstd")
        with pa.ipc.new_file(sink, predictions.schema, options=options) as w:
            w.write_table(predictions)
        _write_atomic(os.path.join(out_dir, "predictions.feather"), sink.getvalue().to_pybytes())
        _write_atomic(os.path.join(out_dir, "matches.json"), json.dumps(matches, indent=2).encode())
    return scenalog.MineResult(
        predictions=predictions,
        submission=submission,
        matches=matches,
        pairs=pairs,
        failures=failures,
        out=None if out is None else os.fspath(out),
    )


def _write_atomic(path: str, data: bytes) -> None:
    tmp = f"{path}.tmp-{os.getpid()}"
    with open(tmp, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)
