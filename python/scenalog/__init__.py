"""Scenalog from Python: mine Argoverse 2 driving logs with Datalog rules.

The functions mirror the ``scenalog`` command and run the same Rust code (the GIL released, so
other threads run meanwhile, and Ctrl-C interrupts a call):

- ``check(text_or_path)`` -> list of diagnostic dicts (``scenalog check --json``)
- ``facts(log_dir)`` -> summary dict; ``facts(log_dir, relation)`` -> ``pyarrow.Table`` (within
  ``max_tuples`` / ``timeout_ms``, as ``scenalog facts --relation``)
- ``mine(rules, logs, ...)`` -> ``MineResult`` (matches, predictions as a ``pyarrow.Table``, ...)
- ``explain(rules, log, track, at)`` -> the proof / why-not report as a dict
- ``evaluate(predictions, ground_truth, dataset_dir=None)`` -> the official metrics as a dict
- ``synthesize(description, candidates=K, ...)`` -> ``Synthesis`` (a program written by an LLM
  server, checked, repaired, and with candidates chosen by what they match on logs)

Errors are raised as ``ScenalogError`` carrying the message the command prints, naming this
package's keyword arguments (``max_tuples``) where the command names its flags
(``--max-tuples``); a missing file is a ``ScenalogFileNotFoundError`` (both a
``ScenalogError`` and a ``FileNotFoundError``), a value out of range a ``ValueError``.
``scenalog.ray.mine`` shards a run across a Ray cluster (``pip install 'scenalog[ray]'``).
"""

from __future__ import annotations

import io
import json
import os
import pickle
import shutil
import tempfile
from dataclasses import dataclass, field
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

import pyarrow as pa
import pyarrow.ipc

from . import _native
from ._native import ScenalogError

__version__: str = _native.__version__
"""The package's version (the Rust workspace's, which the ``scenalog`` command reports)."""


class ScenalogFileNotFoundError(ScenalogError, FileNotFoundError):
    """A file a call names does not exist: the command's message (naming it), and ``errno``
    ``ENOENT`` and ``filename`` set when it is one path."""

    def __str__(self) -> str:
        # The command's message alone, not OSError's "[Errno 2] message: 'filename'".
        return self.strerror if self.strerror is not None else super().__str__()


_native._register_not_found(ScenalogFileNotFoundError)

__all__ = [
    "__version__",
    "ScenalogError",
    "ScenalogFileNotFoundError",
    "MineResult",
    "check",
    "facts",
    "mine",
    "explain",
    "evaluate",
    "Synthesis",
    "synthesize",
]

PathLike = Union[str, "os.PathLike[str]"]


def _is_path_like(x: Any) -> bool:
    return isinstance(x, os.PathLike)


def _looks_like_path(text: str) -> bool:
    """Whether a string given to ``check`` is meant as a path (see ``check``)."""
    line = text.strip()
    if not line or "\n" in line:
        return False
    if line.endswith(".dl"):
        return True
    separators = {"/", os.sep} | ({os.altsep} if os.altsep else set())
    has_separator = any(sep in line for sep in separators)
    return has_separator and "(" not in line and ":-" not in line


def check(
    text_or_path: Union[str, "os.PathLike[str]", None] = None,
    require_referred: bool = True,
    *,
    path: Optional[PathLike] = None,
) -> List[dict]:
    """Checks a rule program: its text, or a ``.dl`` file.

    Which one a string is, in this order:

    - ``path=`` is always read as a file, and so is a ``pathlib.Path`` (any ``os.PathLike``);
    - a one-line string naming an existing file is read as that file;
    - a one-line string that looks like a path is read as a file, and raises
      ``ScenalogFileNotFoundError`` (a ``FileNotFoundError``) naming it when there is none.
      It looks like a path when it ends with ``.dl``, or when it holds a path separator and no
      rule syntax (no ``(`` and no ``:-``): ``check("rules/library/stoped_car.dl")`` raises
      rather than checking the path as program text;
    - anything else is program text (``check('referred(X, T) :- ego(X), present(X, T).')``).

    Returns the diagnostics as ``scenalog check --json`` prints them for that file: dicts with
    ``code``, ``severity``, ``message``, ``line``, ``column``, ... (an empty list when clean).
    ``require_referred=False`` is ``--no-referred``.
    """
    if path is not None:
        if text_or_path is not None:
            raise TypeError("check: give the program's text or path=, not both")
        return json.loads(_native.check("", os.fspath(path), require_referred))
    if _is_path_like(text_or_path):
        return json.loads(_native.check("", os.fspath(text_or_path), require_referred))
    if not isinstance(text_or_path, str):
        raise TypeError(f"check: expected program text or a path, got {type(text_or_path).__name__}")
    text = text_or_path
    one_line = "\n" not in text and text.strip()
    if one_line and (os.path.isfile(text) or _looks_like_path(text)):
        return json.loads(_native.check("", text, require_referred))
    return json.loads(_native.check(text, None, require_referred))


def facts(
    log_dir: PathLike,
    relation: Optional[str] = None,
    *,
    max_tuples: Optional[int] = None,
    timeout_ms: Optional[int] = None,
) -> Union[dict, pa.Table]:
    """A log's facts.

    Without ``relation``: the log's summary as ``scenalog facts LOG --json`` prints it (a dict).
    With it: that catalog relation extracted from the log, as a ``pyarrow.Table`` whose columns
    are the catalog's (tracks as uuid strings, times as frame indices, lanes as map ids), within
    ``max_tuples`` and ``timeout_ms`` (``scenalog facts --relation``'s limits, by default those
    of one ``mine`` pair): a relation past either raises ``ScenalogError`` naming it.
    """
    if relation is None:
        return json.loads(_native.facts_summary(os.fspath(log_dir)))
    data = _native.facts_relation(os.fspath(log_dir), relation, max_tuples=max_tuples, timeout_ms=timeout_ms)
    return pa.ipc.open_stream(data).read_all()


@dataclass
class MineResult:
    """What ``mine`` returns.

    ``predictions``: the predictions as the long Arrow table (``predictions.feather``, or
    ``submission.feather`` with ``log_prompts``); ``submission``: the official pickle's bytes
    (``pickle.loads`` gives the dict the official ``evaluate`` takes); ``matches``: one dict per
    referred track (log_id, description, program, track_uuid, category, first_s, last_s, frames,
    related); ``pairs``: each (log, program) pair's status (``done``, ``resumed``, ``failed``),
    error, number of matches and evaluation seconds (as in ``summary.json``); ``failures``: every failure message (programs that do not check, unreadable logs,
    failed pairs), the rest having run; ``score``: the metrics against ``gt`` (or None);
    ``without_program``: with ``log_prompts``, the prompts no program was found for; ``out``:
    the output directory, or None when the run went to a temporary directory now removed;
    ``report``: with ``report=True``, the path of the report page (``OUT/report/index.html``).
    """

    predictions: pa.Table
    submission: bytes
    matches: List[dict]
    pairs: List[dict]
    failures: List[str]
    score: Optional[dict] = None
    without_program: List[str] = field(default_factory=list)
    out: Optional[str] = None
    report: Optional[str] = None


def _paths(name: str, value: Union[PathLike, Iterable[PathLike], None]) -> List[str]:
    if value is None:
        return []
    if isinstance(value, (str, bytes)) or _is_path_like(value):
        return [os.fspath(value)]
    out = [os.fspath(v) for v in value]
    return out


def mine(
    rules: Union[PathLike, Iterable[PathLike], None] = None,
    logs: Union[PathLike, Iterable[PathLike], None] = None,
    *,
    out: Optional[PathLike] = None,
    threads: Optional[int] = None,
    resume: bool = False,
    gt: Optional[PathLike] = None,
    eval_timestamps: Optional[PathLike] = None,
    max_tuples: Optional[int] = None,
    timeout_ms: Optional[int] = None,
    log_prompts: Optional[PathLike] = None,
    dataset_dir: Optional[PathLike] = None,
    tracks: Optional[PathLike] = None,
    programs: Optional[PathLike] = None,
    confidence_filter: bool = True,
    report: bool = False,
    report_max_pictures: Optional[int] = None,
) -> MineResult:
    """Mines logs with rule programs, as ``scenalog mine`` (same options, same outputs).

    ``rules``: ``.dl`` files or directories of them; ``logs``: log directories or directories
    of logs. ``out``: where to write (``predictions.pkl``, ``predictions.feather``,
    ``matches.json``, ``pairs/`` ...); by default a temporary directory, removed after the
    results are read. ``threads`` (default one per core), ``resume``, ``gt`` (score the run),
    ``eval_timestamps``, ``max_tuples`` and ``timeout_ms`` are the command's flags.
    ``report=True`` also writes the browsable report, ``OUT/report/index.html`` (pictures of up
    to ``report_max_pictures`` matches, default 40); it needs ``out``. The keywords are checked
    as the command checks its flags: ``threads=0`` or ``max_tuples=-1`` raise ``ValueError``
    naming the keyword.

    A split's pairs: ``mine(log_prompts="log_prompt_pairs.json", dataset_dir=SPLIT,
    tracks="tracker.pkl", programs=DIR)`` mines those (log, prompt) pairs only into
    ``submission.pkl`` / ``submission.feather`` (``confidence_filter=False`` is
    ``--no-confidence-filter``); ``rules``, ``logs``, ``gt``, ``eval_timestamps`` and
    ``report`` do not go with ``log_prompts``.

    Raises ``ScenalogError`` when the run cannot start (the command's exit 2: bad arguments,
    missing files, no program that checks); a failing pair or log does not raise, it is listed
    in ``failures`` and the rest is mined.
    """
    rule_list = _paths("rules", rules)
    log_list = _paths("logs", logs)
    if log_prompts is not None:
        _split_conflicts(rules, logs, gt, eval_timestamps, report, dataset_dir)
    else:
        for given, keyword in [
            (dataset_dir is not None, "dataset_dir="),
            (tracks is not None, "tracks="),
            (programs is not None, "programs="),
            (not confidence_filter, "confidence_filter=False"),
        ]:
            if given:
                raise ScenalogError(f"{keyword} goes with log_prompts=")
        if not rule_list or not log_list:
            raise ScenalogError("mine: give rules (.dl files or directories) and logs (log directories)")
    if report and out is None:
        raise ScenalogError("mine: report=True needs out= (the report is a page in the output directory)")
    tmp = None
    if out is None:
        tmp = tempfile.mkdtemp(prefix="scenalog-mine-")
        out_dir = tmp
    else:
        out_dir = os.fspath(out)
    fspath = lambda p: None if p is None else os.fspath(p)  # noqa: E731
    try:
        if log_prompts is not None:
            raw = _native.mine_split(
                os.fspath(log_prompts),
                os.fspath(dataset_dir),
                out_dir,
                tracks=fspath(tracks),
                programs=fspath(programs),
                confidence_filter=confidence_filter,
                threads=threads,
                resume=resume,
                max_tuples=max_tuples,
                timeout_ms=timeout_ms,
            )
        else:
            raw = _native.mine(
                rule_list,
                log_list,
                out_dir,
                threads=threads,
                resume=resume,
                gt=fspath(gt),
                eval_timestamps=fspath(eval_timestamps),
                max_tuples=max_tuples,
                timeout_ms=timeout_ms,
                report=(40 if report_max_pictures is None else report_max_pictures) if report else None,
            )
        result = json.loads(raw)
        table_path = os.path.join(out_dir, result["table"])
        with open(table_path, "rb") as f:
            predictions = pa.ipc.open_file(pa.BufferReader(f.read())).read_all()
        with open(os.path.join(out_dir, result["pickle"]), "rb") as f:
            submission = f.read()
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    return MineResult(
        predictions=predictions,
        submission=submission,
        matches=result["matches"],
        pairs=result["pairs"],
        failures=result["failures"],
        score=result["score"],
        without_program=result["without_program"],
        out=None if tmp is not None else out_dir,
        report=result["report"],
    )


def _split_conflicts(rules, logs, gt, eval_timestamps, report, dataset_dir) -> None:
    """The keywords a split's run (``log_prompts=``) has no use for: an error, not ignored."""
    if rules is not None or logs is not None:
        raise ScenalogError(
            "log_prompts= takes its programs from programs= and the library, and its logs from "
            "dataset_dir=; leave out rules and logs"
        )
    for given, keyword, instead in [
        (gt is not None, "gt=", "score the submission afterwards with evaluate(result.submission, gt)"),
        (eval_timestamps is not None, "eval_timestamps=", "a split's logs are mined at their own timestamps"),
        (report, "report=True", "picture matches with mine(rules, logs, out=..., report=True)"),
    ]:
        if given:
            raise ScenalogError(f"{keyword} does not go with log_prompts=: {instead}")
    if dataset_dir is None:
        raise ScenalogError(
            "log_prompts= needs dataset_dir= (the AV2 split with each log's ego poses and map)"
        )


def explain(
    rules: PathLike,
    log: PathLike,
    track: str,
    at: Optional[float] = None,
    why_not: bool = False,
    *,
    max_tuples: Optional[int] = None,
    timeout_ms: Optional[int] = None,
) -> dict:
    """Why ``track`` (a uuid or an unambiguous prefix) is, or is not, referred by the program
    ``rules`` on ``log`` at ``at`` seconds from the log's start (default: its first referred
    frame): the dict ``scenalog explain --json`` prints (the proof, and the why-not report when
    it is not referred or ``why_not=True``). The program is evaluated within ``max_tuples`` and
    ``timeout_ms`` (``scenalog explain``'s limits, by default those of one ``mine`` pair)."""
    return json.loads(
        _native.explain(
            os.fspath(rules),
            os.fspath(log),
            track,
            None if at is None else float(at),
            why_not,
            max_tuples=max_tuples,
            timeout_ms=timeout_ms,
        )
    )


def _source(what: str, value: Any):
    """A submission as the native evaluator takes it: (kind, value)."""
    if _is_path_like(value) or isinstance(value, str):
        return "path", os.fspath(value)
    if isinstance(value, (bytes, bytearray, memoryview)):
        data = bytes(value)
        return ("arrow", data) if data[:6] == b"ARROW1" else ("pickle", data)
    if isinstance(value, pa.Table):
        sink = io.BytesIO()
        with pa.ipc.new_file(sink, value.schema) as w:
            w.write_table(value)
        return "arrow", sink.getvalue()
    if isinstance(value, dict):
        # The official evaluate's objects: {(log_id, prompt): [frame dicts of numpy arrays]}.
        # Pickled as the official files are, and read by the same reader as those files.
        return "pickle", pickle.dumps(value, protocol=4)
    raise TypeError(
        f"evaluate: {what}: expected a path, pickle or Arrow bytes, a pyarrow.Table or the official "
        f"dict of frames, got {type(value).__name__}"
    )


def evaluate(
    predictions: Any,
    ground_truth: Any,
    dataset_dir: Optional[PathLike] = None,
    max_range_m: float = 50.0,
    rate: Optional[int] = None,
    timestamps: Optional[Dict[str, Sequence[int]]] = None,
) -> dict:
    """The official scenario-mining metrics of ``predictions`` against ``ground_truth``: the
    dict ``scenalog eval --json`` prints (``hota_temporal``, ``hota_track``, the balanced
    accuracies, the paper's ``hota_temporal_related``, ``hota_temporal_other`` and the tracker's
    ``hota`` (``None`` where the ground truth holds no such object), per prompt ...).

    Each side is what the official ``av2`` ``evaluate`` takes (``{(log_id, prompt): [frame
    dict of numpy arrays, ...]}``), a path to an official pickle or a long Arrow table, their
    bytes, or a ``pyarrow.Table``. ``dataset_dir`` turns on the drivable-area filter (the official
    ``dataset_dir``); ``max_range_m`` is the range filter. ``rate`` (Hz, e.g. 2 or 10) or
    ``timestamps`` (``{log_id: [timestamp_ns, ...]}``) evaluate the chosen frames, as
    ``scenalog eval --rate`` / ``--timestamps``.
    """
    pk, pv = _source("predictions", predictions)
    gk, gv = _source("ground_truth", ground_truth)
    ds = None if dataset_dir is None else os.fspath(dataset_dir)
    ts = None if timestamps is None else json.dumps({str(k): [int(t) for t in v] for k, v in timestamps.items()})
    r = None if rate is None else int(rate)
    return json.loads(_native.evaluate(pk, pv, gk, gv, float(max_range_m), ds, r, ts))


@dataclass
class Synthesis:
    """What ``synthesize`` returns.

    ``program``: the kept program's text (with its ``// description:`` line), or the last
    attempt's when none checked clean (``clean`` False); ``transcript``: every round as
    ``scenalog synth --transcript`` writes it (``rounds``, ``outcome``, and with candidates
    ``search``: every candidate, what it matched, why the kept one won; ``evidence``: what the
    model was shown of the kept program's matches and its answer); ``usage``: the tokens the
    server reported over everything asked."""

    description: str
    program: Optional[str]
    clean: bool
    transcript: Dict[str, Any]
    usage: Dict[str, Any] = field(default_factory=dict)

    @property
    def candidates(self) -> List[Dict[str, Any]]:
        """The search's candidates (empty with one candidate)."""
        return list((self.transcript.get("search") or {}).get("candidates", []))


def synthesize(
    description: str,
    *,
    candidates: int = 1,
    logs: Union[PathLike, Iterable[PathLike], None] = None,
    evidence_rounds: Optional[int] = None,
    grammar: Optional[str] = None,
    rounds: int = 3,
    base_url: Optional[str] = None,
    model: Optional[str] = None,
    api_key: Optional[str] = None,
    temperature: Optional[float] = 0.0,
    timeout_s: int = 300,
    retries: int = 4,
    examples: Optional[int] = 8,
    held_out: bool = False,
    max_tokens: Optional[int] = None,
    cache_dir: Optional[PathLike] = None,
) -> Synthesis:
    """Writes a program for ``description`` with an OpenAI-compatible LLM server, as
    ``scenalog synth`` does: the checker's diagnostics sent back for up to ``rounds`` rounds;
    with ``candidates`` above 1, that many candidates, each clean one run on ``logs`` (default:
    the sample logs) and the one whose matches agree most with the others' kept; then
    ``evidence_rounds`` rounds (default 1 with candidates, else 0) showing the model what the
    kept program matches, which it keeps or revises. ``grammar`` (``"llama-cpp"``, ``"vllm"``
    or ``"sglang"``) sends the language's grammar in that server's field. The server, model and
    key default to ``SCENALOG_LLM_BASE_URL``, ``SCENALOG_LLM_MODEL`` and
    ``SCENALOG_LLM_API_KEY``; ``temperature=None`` sends none. Answers are cached in
    ``cache_dir`` when given. An unreachable server is a ``ScenalogError``."""
    text = _native.synthesize(
        description,
        candidates=candidates,
        logs=_paths("logs", logs),
        evidence_rounds=evidence_rounds,
        grammar=grammar,
        rounds=rounds,
        base_url=base_url,
        model=model,
        api_key=api_key,
        temperature=None if temperature is None else float(temperature),
        timeout_s=timeout_s,
        retries=retries,
        examples=examples,
        held_out=held_out,
        max_tokens=max_tokens,
        cache_dir=None if cache_dir is None else os.fspath(cache_dir),
    )
    t = json.loads(text)
    return Synthesis(
        description=t.get("description", description),
        program=t.get("program"),
        clean=bool(t.get("clean")),
        transcript=t,
        usage=t.get("usage") or {},
    )
