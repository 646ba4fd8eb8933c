#!/usr/bin/env python3
"""Prints the figures facts/tests/it/real_logs.rs checks, computed independently with pyarrow + numpy.

Run from the repository root: python3 facts/tests/verify_figures.py
"""
import collections
import glob
import json
import os

import numpy as np
import pyarrow.ipc as ipc

LOGS = "tests/data/av2/logs"


def rot(w, x, y, z):
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


for d in sorted(glob.glob(LOGS + "/*")):
    names = [n for n in ("annotations_with_ego.feather", "annotations.feather") if os.path.exists(f"{d}/{n}")]
    t = ipc.open_file(f"{d}/{names[0]}").read_all().to_pandas()
    p = ipc.open_file(f"{d}/city_SE3_egovehicle.feather").read_all().to_pandas()
    print("==", os.path.basename(d), names[0])
    ts = np.sort(t.timestamp_ns.unique())
    print("rows", len(t), "timestamps", len(ts), "first", ts[0], "last", ts[-1])
    print("duplicate (track, ts) rows", t.duplicated(["track_uuid", "timestamp_ns"]).sum())
    print("tracks by category", dict(sorted(t.groupby("category").track_uuid.nunique().items())))
    print("ego uuids", list(t[t.category == "EGO_VEHICLE"].track_uuid.unique()))
    print("every annotation timestamp has a pose", set(ts) <= set(p.timestamp_ns))
    e0 = p[p.timestamp_ns == ts[0]].iloc[0]
    print("ego t at first ts", repr(float(e0.tx_m)), repr(float(e0.ty_m)), repr(float(e0.tz_m)))
    m = json.load(open(glob.glob(f"{d}/map/log_map_archive_*")[0]))
    ls = m["lane_segments"]
    print("lanes", len(ls), dict(collections.Counter(l["lane_type"] for l in ls.values())),
          "intersection", sum(l["is_intersection"] for l in ls.values()))
    ids = {int(k) for k in ls}
    dangling = set()
    for l in ls.values():
        for x in l["successors"] + l["predecessors"] + [l["left_neighbor_id"], l["right_neighbor_id"]]:
            if x is not None and x not in ids:
                dangling.add(x)
    print("dangling ids", len(dangling), "smallest", min(dangling))
    print("crossings", len(m["pedestrian_crossings"]), "drivable areas", len(m["drivable_areas"]))
    first = sorted(t[t.category != "EGO_VEHICLE"].track_uuid.unique())[0]
    rows = t[t.track_uuid == first].sort_values("timestamp_ns")
    s = rows.iloc[0]
    e = p[p.timestamp_ns == s.timestamp_ns].iloc[0]
    re = rot(e.qw, e.qx, e.qy, e.qz)
    c = re @ np.array([s.tx_m, s.ty_m, s.tz_m]) + np.array([e.tx_m, e.ty_m, e.tz_m])
    r = re @ rot(s.qw, s.qx, s.qy, s.qz)
    print("first track", first, s.category, "boxes", len(rows), "first box city centre",
          [repr(float(v)) for v in c], "city yaw", repr(float(np.arctan2(r[1, 0], r[0, 0]))))
