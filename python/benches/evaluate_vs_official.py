"""`scenalog.evaluate` against the official av2 `evaluate`, same process, same objects.

Run from the repository's root in an environment with both packages:
    python python/benches/evaluate_vs_official.py [RUNS]
Each side scores the fixture (tests/data/av2/eval: predictions and ground truth loaded once with
pickle, as a user holding them would) RUNS times (default 5); prints the medians, the ratio and
the headline numbers of both, which must agree.
"""

import copy
import pickle
import statistics
import sys
import tempfile
import time
import warnings

warnings.filterwarnings("ignore")

import scenalog
from av2.evaluation.scenario_mining.eval import evaluate as official_evaluate

EVAL = "tests/data/av2/eval"
RUNS = int(sys.argv[1]) if len(sys.argv) > 1 else 5

with open(f"{EVAL}/combined_predictions_dev.pkl", "rb") as f:
    pred = pickle.load(f)
with open(f"{EVAL}/combined_gt_dev.pkl", "rb") as f:
    gt = pickle.load(f)


def run_official():
    # The official code relabels and filters its inputs in place: give it fresh copies (the
    # copies are made outside the timed region).
    p, g = copy.deepcopy(pred), copy.deepcopy(gt)
    with tempfile.TemporaryDirectory() as out:
        t = time.perf_counter()
        result = official_evaluate(p, g, "HOTA", 50, None, out)
        return time.perf_counter() - t, result


def run_scenalog():
    t = time.perf_counter()
    r = scenalog.evaluate(pred, gt)
    return time.perf_counter() - t, (r["hota_temporal"], r["hota_track"], r["timestamp_ba"], r["log_ba"])


official_times, ours_times = [], []
for _ in range(RUNS):
    t, official = run_official()
    official_times.append(t)
    t, ours = run_scenalog()
    ours_times.append(t)

mo, ms = statistics.median(official_times), statistics.median(ours_times)
print(f"official av2 evaluate: median {mo * 1e3:.1f} ms over {RUNS} runs (min {min(official_times) * 1e3:.1f}, max {max(official_times) * 1e3:.1f})")
print(f"scenalog.evaluate:     median {ms * 1e3:.1f} ms over {RUNS} runs (min {min(ours_times) * 1e3:.1f}, max {max(ours_times) * 1e3:.1f})")
print(f"ratio: {mo / ms:.1f}x")
print("official:", tuple(float(x) for x in official))
print("scenalog:", ours)
worst = max(abs(float(a) - b) for a, b in zip(official, ours))
print(f"largest difference in the headline: {worst:.3g}")
