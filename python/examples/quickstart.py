"""Scenalog from Python on the bundled sample logs: run from the repository's root."""

import scenalog

logs = "tests/data/av2/logs"
rules = ["rules/library/stopped_car.dl", "rules/library/vehicle_with_bicycle_to_its_right.dl"]

# Is the program well formed? (an empty list: no diagnostics)
print(scenalog.check(rules[0]))

# One relation of one log, as a pyarrow.Table.
speed = scenalog.facts(f"{logs}/3bffdcff-c3a7-38b6-a0f2-64196d130958", "speed")
print(speed.num_rows, speed.column_names)

# Mine both programs over the three logs; predictions is the long Arrow table.
run = scenalog.mine(rules, logs)
print(run.predictions.num_rows, "prediction rows,", len(run.matches), "matched tracks")

# Why did the first stopped car match?
m = next(m for m in run.matches if m["program"] == "stopped_car")
why = scenalog.explain(rules[0], f"{logs}/{m['log_id']}", m["track_uuid"], at=m["first_s"])
print(why["referred"], [fact["text"] for fact in why["proof"]["body"]])

# The official metrics, from files or from the objects the official evaluate takes.
metrics = scenalog.evaluate(
    "tests/data/av2/eval/combined_predictions_dev.pkl", "tests/data/av2/eval/combined_gt_dev.pkl"
)
print(metrics["hota_temporal"], metrics["hota_track"], metrics["timestamp_ba"], metrics["log_ba"])
