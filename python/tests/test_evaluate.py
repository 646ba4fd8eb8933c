"""`scenalog.evaluate` against `scenalog eval --json` (to 1e-12) and the official numbers."""

import json
import math
import pickle

import pyarrow as pa
import pyarrow.ipc
import pytest

import scenalog
from conftest import EVAL, HOLDOUT, LOGS, cli_message

GT = EVAL / "combined_gt_dev.pkl"
PRED = EVAL / "combined_predictions_dev.pkl"
HOLDOUTS = sorted(HOLDOUT.glob("*.pkl"))


def assert_close(got, want, where="report"):
    """Same keys and structure; numbers equal to 1e-12 (NaN equals NaN)."""
    if isinstance(want, dict):
        assert isinstance(got, dict) and sorted(got) == sorted(want), where
        for k in want:
            assert_close(got[k], want[k], f"{where}.{k}")
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), where
        for i, (g, w) in enumerate(zip(got, want)):
            assert_close(g, w, f"{where}[{i}]")
    elif isinstance(want, float) or isinstance(got, float):
        if want is None or got is None:
            assert got == want, where
        elif math.isnan(want):
            assert math.isnan(got), where
        else:
            assert abs(got - want) <= 1e-12, f"{where}: {got} != {want}"
    else:
        assert got == want, where


def test_fixture_official_numbers():
    r = scenalog.evaluate(PRED, GT)
    assert abs(r["hota_temporal"] - 0.3795501973683041) <= 1e-12
    assert abs(r["hota_track"] - 0.3941392002747208) <= 1e-12
    assert r["timestamp_ba"] == pytest.approx(0.85, abs=1e-12)
    assert r["log_ba"] == pytest.approx(1.0, abs=1e-12)
    roi = scenalog.evaluate(PRED, GT, dataset_dir=LOGS)
    assert abs(roi["hota_temporal"] - 0.38316587964415044) <= 1e-12
    assert abs(roi["hota_track"] - 0.4016635999319241) <= 1e-12


def test_related_other_and_tracker_hota():
    """The paper's further columns, as `scenalog eval --json` (eval/README.md): the fixture
    labels no object related (None), other and the tracker's HOTA as pinned in eval's tests."""
    r = scenalog.evaluate(PRED, GT)
    assert r["hota_temporal_related"] is None
    assert r["hota_temporal_related_by_prompt"] == {"stopped car": None, "vehicle with a bicycle to its right": None}
    assert abs(r["hota_temporal_other"] - 0.5807763575364608) <= 1e-12
    assert abs(r["hota"] - 0.7466950270710451) <= 1e-12
    assert abs(r["hota_by_prompt"]["stopped car"]["value"] - 0.7583319113505939) <= 1e-12
    assert r["warnings"] == []
    roi = scenalog.evaluate(PRED, GT, dataset_dir=LOGS)
    assert abs(roi["hota_temporal_other"] - 0.5715236915701356) <= 1e-12
    assert abs(roi["hota"] - 0.7537326721599327) <= 1e-12


def test_ground_truth_against_itself_is_one_on_every_defined_key():
    with open(GT, "rb") as f:
        gt_obj = pickle.load(f)
    import numpy as np

    pred = {
        k: [dict(fr, score=np.ones(len(fr["track_id"]), dtype=np.float32)) for fr in frames]
        for k, frames in gt_obj.items()
    }
    r = scenalog.evaluate(pred, gt_obj)
    for k in ["hota_temporal", "hota_track", "timestamp_ba", "log_ba", "hota_temporal_other", "hota"]:
        assert abs(r[k] - 1.0) <= 1e-12, k
    assert r["hota_temporal_related"] is None


def test_rate_and_timestamps(cli_json, tmp_path):
    assert_close(scenalog.evaluate(PRED, GT, rate=2), scenalog.evaluate(PRED, GT))
    with pytest.raises(scenalog.ScenalogError, match="cannot be sampled at 10 Hz"):
        scenalog.evaluate(PRED, GT, rate=10)
    with open(GT, "rb") as f:
        gt_obj = pickle.load(f)
    first = {k[0]: [int(frames[0]["timestamp_ns"])] for k, frames in gt_obj.items()}
    path = tmp_path / "ts.json"
    path.write_text(json.dumps(first))
    want = cli_json("eval", "--json", "--pred", PRED, "--gt", GT, "--timestamps", path)
    assert_close(scenalog.evaluate(PRED, GT, timestamps=first), want)
    with pytest.raises(ValueError):
        scenalog.evaluate(PRED, GT, rate=2, timestamps=first)


# The drivable-area filter on the fixture and one holdout submission (building the rasters is
# the slow part in a debug build); every submission without it.
CASES = [(p, False) for p in [PRED, *HOLDOUTS]] + [(PRED, True), (HOLDOUT / "holdout_drop_frames.pkl", True)]


@pytest.mark.parametrize("pred,roi", CASES, ids=lambda x: x.stem if hasattr(x, "stem") else ("roi" if x else "no_roi"))
def test_equals_the_command(pred, roi, cli_json):
    extra = ["--dataset-dir", LOGS] if roi else []
    want = cli_json("eval", "--json", "--pred", pred, "--gt", GT, *extra)
    got = scenalog.evaluate(pred, GT, dataset_dir=LOGS if roi else None)
    assert_close(got, want)


def test_the_official_objects_bytes_and_tables():
    """The dicts of numpy arrays the official `evaluate` takes, bytes and Arrow tables."""
    want = scenalog.evaluate(PRED, GT)
    with open(PRED, "rb") as f:
        pred_obj = pickle.load(f)
    with open(GT, "rb") as f:
        gt_obj = pickle.load(f)
    assert isinstance(pred_obj, dict) and isinstance(next(iter(pred_obj)), tuple)
    assert_close(scenalog.evaluate(pred_obj, gt_obj), want)
    assert_close(scenalog.evaluate(PRED.read_bytes(), str(GT)), want)
    pred_table = pa.ipc.open_file(pa.memory_map(str(EVAL / "combined_predictions_dev.feather"))).read_all()
    gt_table = pa.ipc.open_file(pa.memory_map(str(EVAL / "combined_gt_dev.feather"))).read_all()
    assert_close(scenalog.evaluate(pred_table, gt_table), want)
    assert_close(scenalog.evaluate(EVAL / "combined_predictions_dev.feather", gt_obj), want)


def test_errors_carry_the_command_messages(tmp_path, cli):
    corrupt = tmp_path / "corrupt.pkl"
    corrupt.write_bytes(PRED.read_bytes()[:5000])
    code, _, err = cli("eval", "--pred", corrupt, "--gt", GT)
    assert code == 2
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.evaluate(corrupt, GT)
    assert str(e.value) == cli_message(err, "eval")
    missing = tmp_path / "missing.pkl"
    _, _, err = cli("eval", "--pred", missing, "--gt", GT)
    with pytest.raises(scenalog.ScenalogError) as e:
        scenalog.evaluate(missing, GT)
    assert str(e.value) == cli_message(err, "eval")
    with pytest.raises(scenalog.ScenalogError, match="dataset_dir"):
        scenalog.evaluate(PRED, GT, dataset_dir=tmp_path)
    with pytest.raises(TypeError):
        scenalog.evaluate(42, GT)
    with pytest.raises(ValueError):
        scenalog.evaluate(PRED, GT, max_range_m=float("inf"))
