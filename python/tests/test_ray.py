"""`scenalog.ray.mine` on a local Ray instance (2 CPUs) against the single-process run."""

import json
import pickle

import pytest

import scenalog
import scenalog.ray
from conftest import LIBRARY, LOG_IDS, LOGS, PROGRAMS

ray = pytest.importorskip("ray", reason="Ray is not installed (pip install 'scenalog[ray]')")


@pytest.fixture(scope="module")
def local_ray(tmp_path_factory):
    crash_dir = tmp_path_factory.mktemp("crash-once")
    # Every log's first attempt kills its worker: the run only succeeds through Ray's retries.
    ray.init(
        num_cpus=2,
        include_dashboard=False,
        runtime_env={"env_vars": {"SCENALOG_RAY_TEST_CRASH_ONCE_DIR": str(crash_dir)}},
    )
    yield crash_dir
    ray.shutdown()


def test_ray_equals_the_single_process_run(local_ray, tmp_path):
    single = scenalog.mine(PROGRAMS, LOGS, threads=2)
    distributed = scenalog.ray.mine(PROGRAMS, LOGS, out=tmp_path / "out", max_retries=2)
    # Each log's task crashed once and was retried.
    assert sorted(p.name for p in local_ray.iterdir()) == LOG_IDS
    assert distributed.failures == []
    assert distributed.submission == single.submission
    assert distributed.predictions.equals(single.predictions)
    assert distributed.matches == single.matches
    keys = [(p["log_id"], p["program"]) for p in distributed.pairs]
    assert len(keys) == len(set(keys)) == len(LOG_IDS) * len(PROGRAMS)
    assert (tmp_path / "out" / "predictions.pkl").read_bytes() == single.submission
    assert json.loads((tmp_path / "out" / "matches.json").read_text()) == single.matches


def test_ray_lists_bad_programs_and_mines_the_rest(local_ray, tmp_path):
    bad = tmp_path / "bad.dl"
    bad.write_text("referred(X, T) :- nonsense(X, T).\n")
    result = scenalog.ray.mine([PROGRAMS[0], bad], LOGS)
    assert len(result.failures) == 1 and "bad.dl" in result.failures[0]
    assert result.submission == scenalog.mine(PROGRAMS[0], LOGS).submission
    with pytest.raises(scenalog.ScenalogError, match="no program to mine"):
        scenalog.ray.mine([bad], LOGS)
