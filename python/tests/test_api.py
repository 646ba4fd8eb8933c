"""The package's functions on the sample logs, against the `scenalog` command's own output."""

import errno
import json
import os
import pickle
import shutil
import signal
import threading
import time

import numpy as np
import pyarrow as pa
import pytest

import scenalog
from conftest import DATA, EVAL, LIBRARY, LOG_IDS, LOGS, PROGRAMS, TRACKER, cli_message


def test_check_text_path_and_diagnostics(cli_json):
    assert scenalog.check(LIBRARY / "stopped_car.dl") == []
    assert scenalog.check(str(LIBRARY / "stopped_car.dl")) == []
    text = 'referred(X, T) :- categry(X, "PEDESTRIAN"), present(X, T).\n'
    diags = scenalog.check(text)
    assert [d["code"] for d in diags] == ["E0101"]
    assert "unknown predicate `categry`" in diags[0]["message"]
    assert diags[0]["line"] == 1


def test_check_equals_the_command(tmp_path, cli):
    bad = tmp_path / "bad.dl"
    bad.write_text('referred(X, T) :- category(X, "PEDESTRIAN"), velocity(X, T, V), V > "fast".\n')
    code, out, _ = cli("check", "--json", bad)
    assert code == 1
    assert scenalog.check(bad) == json.loads(out)[0]["diagnostics"]
    assert scenalog.check(bad.read_text()) == json.loads(out)[0]["diagnostics"]


def test_check_missing_file_raises_the_command_message(tmp_path, cli):
    missing = tmp_path / "missing.dl"
    _, _, err = cli("check", missing)
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.check(missing)
    assert str(e.value) == cli_message(err, "check")
    assert isinstance(e.value, FileNotFoundError) and e.value.filename == str(missing)
    # A directory is there, but is no program: not a FileNotFoundError.
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.check(tmp_path)
    assert not isinstance(e.value, FileNotFoundError)


def test_check_a_mistyped_path_raises_file_not_found(tmp_path, monkeypatch):
    """A string that looks like a path is read as one: a typo is FileNotFoundError naming it,
    not the typo checked as program text (which gave four syntax errors)."""
    from conftest import REPO

    monkeypatch.chdir(REPO)
    assert scenalog.check("rules/library/stopped_car.dl") == []
    for typo in ["rules/library/stopped_cra.dl", "stopped_cra.dl", str(tmp_path / "no" / "program")]:
        with pytest.raises(FileNotFoundError) as e:
            scenalog.check(typo)
        assert e.value.filename == typo and e.value.errno == errno.ENOENT
        assert typo in str(e.value)
        assert isinstance(e.value, scenalog.ScenalogError)
    with pytest.raises(FileNotFoundError):
        scenalog.check(path="stopped_car")
    assert scenalog.check(path=LIBRARY / "stopped_car.dl") == []
    # Program text, one line with rule syntax (and a `/` in a comment), is still checked.
    diags = scenalog.check('referred(X, T) :- categry(X, "BUS"), present(X, T). // a/b')
    assert [d["code"] for d in diags] == ["E0101"]
    assert scenalog.check("referred(X, T) :- ego(X), present(X, T).") == []
    with pytest.raises(TypeError):
        scenalog.check("referred(X, T) :- ego(X), present(X, T).", path="x.dl")


def test_version_is_the_packages_and_the_commands(cli):
    import importlib.metadata

    assert scenalog.__version__ == importlib.metadata.version("scenalog")
    code, out, _ = cli("--version")
    assert code == 0 and out.split() == ["scenalog", scenalog.__version__]


def test_facts_summary_and_relation(cli_json):
    log = LOGS / LOG_IDS[0]
    summary = scenalog.facts(log)
    expected = cli_json("facts", "--json", log)
    summary.pop("load_ms"), expected.pop("load_ms")
    assert summary == expected
    for relation in ["category", "speed", "in_lane", "frame_ns", "lane_type"]:
        table = scenalog.facts(log, relation)
        assert isinstance(table, pa.Table)
        rows = cli_json("facts", "--json", "--relation", relation, log)
        assert table.num_rows == len(rows) > 0
        got = [list(r.values()) for r in table.to_pylist()]
        assert got == rows


def test_facts_errors(tmp_path, cli):
    with pytest.raises(scenalog.ScenalogError, match="not a relation of the catalog"):
        scenalog.facts(LOGS / LOG_IDS[0], "no_such_relation")
    missing = tmp_path / "no-log"
    _, _, err = cli("facts", missing)
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.facts(missing)
    assert str(e.value) == cli_message(err, "facts")


def test_facts_relation_within_the_commands_limits(cli):
    """``facts`` extracts within ``scenalog facts --relation``'s limits: past the tuple budget it
    raises the command's message, naming the keyword to raise where the command names its flag."""
    log = LOGS / LOG_IDS[0]
    code, _, err = cli("facts", log, "--relation", "near", "--max-tuples", 10)
    assert code == 2
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.facts(log, "near", max_tuples=10)
    assert cli_message(err, "facts").endswith(" or raise --max-tuples")
    assert str(e.value) == cli_message(err, "facts").replace("--max-tuples", "max_tuples=")
    with pytest.raises(ValueError, match="max_tuples"):
        scenalog.facts(log, "near", max_tuples=0)
    assert scenalog.facts(log, "near", timeout_ms=60_000).num_rows > 10


def test_facts_corrupt_file(tmp_path, cli):
    log = tmp_path / LOG_IDS[0]
    shutil.copytree(LOGS / LOG_IDS[0], log)
    ann = next(p for p in log.iterdir() if p.name.startswith("annotations") and p.suffix == ".feather")
    data = ann.read_bytes()
    ann.write_bytes(data[: len(data) // 3])
    code, _, err = cli("facts", log)
    assert code == 2
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.facts(log)
    assert str(e.value) == cli_message(err, "facts")
    assert ann.name in str(e.value)


def test_mine_equals_the_command(tmp_path, cli_json):
    out = tmp_path / "cli"
    expected = cli_json("mine", "--rules", *PROGRAMS, "--logs", LOGS, "--out", out, "--pickle", "--format", "json")
    result = scenalog.mine(PROGRAMS, LOGS, threads=2)
    assert result.out is None
    assert result.failures == [] == expected["failures"]
    assert result.matches == expected["matches"] and len(result.matches) > 0
    assert result.submission == (out / "predictions.pkl").read_bytes()
    with pa.memory_map(str(out / "predictions.feather")) as f:
        assert result.predictions.equals(pa.ipc.open_file(f).read_all())
    assert len(result.pairs) == len(PROGRAMS) * len(LOG_IDS)
    assert {p["status"] for p in result.pairs} == {"done"}
    # The official pickle's dict, as the official evaluate takes it.
    sub = pickle.loads(result.submission)
    assert {k[0] for k in sub} == set(LOG_IDS)


def test_mine_threads_and_out_dir(tmp_path):
    one = scenalog.mine(PROGRAMS[:2], LOGS, threads=1, out=tmp_path / "one")
    assert one.out == str(tmp_path / "one") and (tmp_path / "one" / "matches.json").is_file()
    two = scenalog.mine(PROGRAMS[:2], LOGS, threads=2)
    assert one.submission == two.submission and one.predictions.equals(two.predictions)
    again = scenalog.mine(PROGRAMS[:2], LOGS, threads=1, out=tmp_path / "one", resume=True)
    assert {p["status"] for p in again.pairs} == {"resumed"}
    assert again.submission == one.submission


def test_mine_scores_against_gt(cli_json, tmp_path):
    # The library's programs for the two prompts of the bundled ground truth.
    scored = [LIBRARY / "stopped_car.dl", LIBRARY / "vehicle_with_bicycle_to_its_right.dl"]
    result = scenalog.mine(scored, LOGS, gt=EVAL / "combined_gt_dev.pkl", out=tmp_path / "m")
    assert result.score is not None
    expected = cli_json("eval", "--json", "--pred", tmp_path / "m" / "scored.pkl", "--gt", EVAL / "combined_gt_dev.pkl")
    assert result.score == expected


def test_mine_report_is_written_as_the_command_writes_it(tmp_path, cli):
    # The library's stopped-car program on the sample logs, pictured: the page and its pictures
    # are in the same published output as the predictions, as `scenalog mine --report` does it.
    program = [LIBRARY / "stopped_car.dl"]
    result = scenalog.mine(program, LOGS, out=tmp_path / "py", report=True, report_max_pictures=2)
    page = tmp_path / "py" / "report" / "index.html"
    assert result.report == str(page) and page.is_file()
    code, _, err = cli("mine", "--rules", *program, "--logs", LOGS, "--out", tmp_path / "cli", "--report", "--report-max-pictures", "2")
    assert code == 0, err
    cli_page = tmp_path / "cli" / "report" / "index.html"
    assert sorted(p.name for p in (page.parent / "img").iterdir()) == sorted(p.name for p in (cli_page.parent / "img").iterdir())
    assert len(list((page.parent / "img").iterdir())) > 0
    assert scenalog.mine(program, LOGS).report is None
    with pytest.raises(scenalog.ScenalogError, match="needs out="):
        scenalog.mine(program, LOGS, report=True)
    with pytest.raises(scenalog.ScenalogError, match="report=True does not go with log_prompts="):
        scenalog.mine(log_prompts=TRACKER / "log_prompt_pairs_sample.json", dataset_dir=LOGS, out=tmp_path / "s", report=True)


def test_mine_log_prompts_with_tracker(tmp_path, cli, cli_json):
    pairs = TRACKER / "log_prompt_pairs_sample.json"
    out = tmp_path / "cli"
    code, _, err = cli("mine", "--log-prompts", pairs, "--dataset-dir", LOGS, "--tracks", TRACKER / "noisy.pkl", "--out", out)
    assert code in (0, 1), err
    result = scenalog.mine(log_prompts=pairs, dataset_dir=LOGS, tracks=TRACKER / "noisy.pkl")
    assert result.submission == (out / "submission.pkl").read_bytes()
    listed = {(log, p) for log, ps in json.loads(pairs.read_text()).items() for p in ps}
    assert set(pickle.loads(result.submission)) == listed


def test_mine_errors(tmp_path, cli):
    bad = tmp_path / "bad.dl"
    bad.write_text("referred(X, T) :- nonsense(X, T).\n")
    code, _, err = cli("mine", "--rules", bad, "--logs", LOGS, "--out", tmp_path / "o")
    assert code == 1
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.mine([bad], LOGS)
    message = str(e.value)
    assert message.startswith("no program to mine")
    assert cli_message(err.splitlines()[0] + "\n", "mine") in message  # the program's own error
    missing = tmp_path / "missing-log"
    _, _, err = cli("mine", "--rules", PROGRAMS[0], "--logs", missing, "--out", tmp_path / "o")
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.mine(PROGRAMS[0], missing)
    # The command's message, naming the keyword where the command names its flag.
    assert cli_message(err, "mine").startswith("--logs: ")
    assert str(e.value) == "logs: " + cli_message(err, "mine")[len("--logs: "):]
    for keyword, value in [("threads", 0), ("max_tuples", 0), ("timeout_ms", -5)]:
        with pytest.raises(ValueError) as e:
            scenalog.mine(PROGRAMS[0], LOGS, **{keyword: value})
        assert str(e.value).startswith(f"{keyword}: ") and "--" not in str(e.value)
    with pytest.raises(scenalog.ScenalogError, match="dataset_dir= goes with log_prompts="):
        scenalog.mine(PROGRAMS[0], LOGS, dataset_dir=LOGS)


def test_errors_name_keywords_not_flags(tmp_path, cli):
    """Every message that reaches Python names the keyword argument, where the command's names
    its flag: a bad timestamps file, and a pair past its tuple budget."""
    bad = tmp_path / "ts.json"
    bad.write_text("[1, 2]")
    _, _, err = cli("mine", "--rules", PROGRAMS[0], "--logs", LOGS, "--eval-timestamps", bad, "--out", tmp_path / "o")
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.mine(PROGRAMS[0], LOGS, eval_timestamps=bad)
    assert cli_message(err, "mine").startswith("--eval-timestamps: ")
    assert str(e.value) == "eval_timestamps: " + cli_message(err, "mine")[len("--eval-timestamps: "):]
    code, out, _ = cli("mine", "--rules", PROGRAMS[0], "--logs", LOGS, "--max-tuples", 1, "--out", tmp_path / "c", "--format", "json")
    assert code == 1
    cli_failures = json.loads(out)["failures"]
    assert any("raise --max-tuples" in f for f in cli_failures)
    result = scenalog.mine(PROGRAMS[0], LOGS, max_tuples=1)
    assert result.failures == [f.replace("--max-tuples", "max_tuples=") for f in cli_failures]
    assert not any("--max-tuples" in f for f in result.failures)
    errors = [p["error"] for p in result.pairs if p["status"] == "failed"]
    assert sorted(errors) == sorted(result.failures)


def test_mine_with_a_corrupt_log_mines_the_rest(tmp_path):
    logs = tmp_path / "logs"
    shutil.copytree(LOGS, logs)
    ann = next(p for p in (logs / LOG_IDS[1]).iterdir() if p.name.startswith("annotations") and p.suffix == ".feather")
    ann.write_bytes(b"ARROW1\x00\x00garbage")
    result = scenalog.mine(PROGRAMS[:1], logs)
    assert any(LOG_IDS[1] in f and ann.name in f for f in result.failures)
    assert {k[0] for k in pickle.loads(result.submission)} == {LOG_IDS[0], LOG_IDS[2]}


def test_explain_equals_the_command(cli_json):
    result = scenalog.mine(PROGRAMS[:1], LOGS)
    m = result.matches[0]
    log = LOGS / m["log_id"]
    got = scenalog.explain(PROGRAMS[0], log, m["track_uuid"], at=m["first_s"])
    assert got["referred"] is True and got["proof"] is not None
    assert got == cli_json("explain", "--json", "--rules", PROGRAMS[0], "--log", log, "--track", m["track_uuid"], "--at", m["first_s"])
    why = scenalog.explain(PROGRAMS[0], log, m["track_uuid"], at=0.0, why_not=True)
    assert why == cli_json("explain", "--json", "--why-not", "--rules", PROGRAMS[0], "--log", log, "--track", m["track_uuid"], "--at", 0)
    assert why["why_not"] is not None


def test_explain_errors(cli):
    log = LOGS / LOG_IDS[0]
    _, _, err = cli("explain", "--rules", PROGRAMS[0], "--log", log, "--track", "no-such-track")
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.explain(PROGRAMS[0], log, "no-such-track")
    assert str(e.value) == cli_message(err, "explain")
    with pytest.raises(ValueError):
        scenalog.explain(PROGRAMS[0], log, "x", at=float("nan"))
    with pytest.raises(ValueError, match="timeout_ms"):
        scenalog.explain(PROGRAMS[0], log, "x", timeout_ms=0)


def test_explain_within_the_commands_limits(cli):
    """``explain`` evaluates within ``scenalog explain``'s limits: past the tuple budget it
    raises the command's message with the keyword to raise."""
    result = scenalog.mine(PROGRAMS[:1], LOGS)
    m = result.matches[0]
    log = LOGS / m["log_id"]
    code, _, err = cli("explain", "--rules", PROGRAMS[0], "--log", log, "--track", m["track_uuid"], "--max-tuples", 1)
    assert code == 1
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.explain(PROGRAMS[0], log, m["track_uuid"], max_tuples=1)
    assert "--max-tuples" in cli_message(err, "explain")
    assert str(e.value) == cli_message(err, "explain").replace("--max-tuples", "max_tuples=")


def test_ctrl_c_interrupts_a_long_call_and_threads_run_meanwhile(tmp_path):
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.01)

    t = threading.Thread(target=ticker)
    t.start()
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # The whole library on every sample log: far longer than a second.
            scenalog.mine(LIBRARY, LOGS, threads=1, out=tmp_path / "run")
    finally:
        timer.cancel()
        stop.set()
        t.join()
    # The GIL was released: the other thread ran during the call.
    assert len(ticks) > 10
    # The run stopped: nothing published, fewer pair records than pairs.
    assert not (tmp_path / "run" / "predictions.pkl").exists()
    programs = len(list(LIBRARY.glob("*.dl")))
    records = list((tmp_path / "run" / "pairs").rglob("*.json"))
    assert len(records) < programs * len(LOG_IDS)


def test_the_readme_example_runs(tmp_path):
    """python/examples/quickstart.py, the README's example, as a new user runs it."""
    import subprocess
    import sys

    from conftest import REPO

    p = subprocess.run(
        [sys.executable, "python/examples/quickstart.py"], cwd=REPO, capture_output=True, text=True
    )
    assert p.returncode == 0, p.stderr
    # Every line as the README shows it (the block after the example), so the shown output
    # cannot go stale: the proof is the prelude's `stopped(...)`, not `speed(...)` lines.
    readme = (REPO / "README.md").read_text()
    example = readme.split("this is `python/examples/quickstart.py`", 1)[1]
    shown = example.split("```\n\n```\n", 1)[1].split("\n```", 1)[0]
    assert p.stdout.splitlines() == shown.splitlines()
    assert shown.splitlines()[-1] == "0.3795501973683041 0.3941392002747208 0.85 1.0"
