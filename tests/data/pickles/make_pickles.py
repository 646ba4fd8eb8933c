#!/usr/bin/env python3
"""Writes the pickle fixtures of tests/data/pickles the way users write them.

    python3 tests/data/pickles/make_pickles.py [OUT_DIR]   # default: this script's directory

Needs numpy; pandas is used when present (a DataFrame's `.to_numpy()` of several columns gives a
Fortran-order array, of a text column an object array). Every file holds the same boxes, so a
reader must decode each to `expected.json`:

- submission_p{0..5}.pkl: the scenario-mining format `{(log_id, prompt): [frame, ...]}`, written
  with `pickle.dump(obj, f, protocol=N)`;
- tracks_p{0..5}.pkl: the AV2 3D-tracking format `{log_id: [frame, ...]}`, the same way.

Each file has one frame per array layout: C order, Fortran order (pandas or
`np.asfortranarray`), non-contiguous views (a column slice, every other row), big-endian dtypes,
narrow widths (float16, int8/int16, uint8/uint16/uint32) and strings as `<U`, `|S` and object
arrays. Nothing random: the output is the same byte for byte on every run with the same
Python and numpy.
"""

import json
import os
import pickle
import sys

import numpy as np

try:
    import pandas as pd
except ImportError:  # pandas is optional: Fortran order then comes from numpy itself.
    pd = None

LOG = "3b3570b4-7b0b-3268-a571-b0889dbf40b6"
PROMPT = "vehicle with a bicycle to its right"
T0 = 315_968_000_000_000_000
# Values exact in float16 as well, so every width decodes to the same numbers.
TRANSLATION = [[10.5, -2.25, 0.5], [11.0, 3.75, 0.25], [-4.5, 8.0, 1.0], [0.125, 0.0, -0.5]]
SIZE = [[4.5, 2.0, 1.5], [1.75, 0.75, 1.25], [0.5, 0.5, 1.75], [12.0, 2.5, 3.5]]
YAW = [0.0, 1.5, -3.0, 0.25]
VELOCITY = [[1.0, 0.5, 0.0], [0.0, 0.0, 0.0], [-2.0, 1.0, 0.0], [0.25, 0.25, 0.0]]
NAME = ["REGULAR_VEHICLE", "BICYCLIST", "PEDESTRIAN", "BUS"]
LABEL = [0, 1, 2, 2]
TRACK_ID = [7, 8, 300, 40000]
SCORE = [0.5, 0.75, 1.0, 0.25]
LAYOUTS = ["c_order", "fortran", "views", "big_endian", "narrow", "object_strings"]


def fortran(rows, dtype):
    """A Fortran-order array, made as pandas users get one."""
    if pd is not None:
        df = pd.DataFrame(rows, columns=["a", "b", "c"]).astype(dtype)
        a = df[["a", "b", "c"]].to_numpy()
    else:
        a = np.asfortranarray(np.array(rows, dtype=dtype))
    assert a.flags.f_contiguous and not a.flags.c_contiguous
    return a


def view_of(rows, dtype):
    """A non-contiguous view: every other row of a larger array, first three columns of four."""
    big = np.zeros((2 * len(rows), 4), dtype=dtype)
    big[::2, :3] = rows
    v = big[::2, :3]
    assert not v.flags.c_contiguous and not v.flags.f_contiguous
    return v


def view_1d(values, dtype):
    big = np.zeros(2 * len(values), dtype=dtype)
    big[::2] = values
    return big[::2]


def strings(layout):
    if layout == "object_strings":
        if pd is not None:
            return pd.Series(NAME, dtype=object).to_numpy()
        return np.array(NAME, dtype=object)
    if layout == "narrow":
        return np.array([n.encode() for n in NAME], dtype="S")
    if layout == "big_endian":
        return np.array(NAME).astype(">U20")
    return np.array(NAME)


def arrays(layout):
    """The frame's arrays in one layout."""
    if layout == "fortran":
        return dict(
            translation_m=fortran(TRANSLATION, "float64"),
            size=fortran(SIZE, "float32"),
            yaw=np.array(YAW, dtype="float32"),
            velocity_m_per_s=fortran(VELOCITY, "float64"),
            label=np.array(LABEL, dtype="int64"),
            track_id=np.array(TRACK_ID, dtype="int64"),
            score=np.array(SCORE, dtype="float32"),
        )
    if layout == "views":
        return dict(
            translation_m=view_of(TRANSLATION, "float64"),
            size=view_of(SIZE, "float32"),
            yaw=view_1d(YAW, "float32"),
            velocity_m_per_s=view_of(VELOCITY, "float64"),
            label=view_1d(LABEL, "int32"),
            track_id=view_1d(TRACK_ID, "int64"),
            score=view_1d(SCORE, "float64"),
        )
    if layout == "big_endian":
        return dict(
            translation_m=np.array(TRANSLATION, dtype=">f8"),
            size=np.array(SIZE, dtype=">f4"),
            yaw=np.array(YAW, dtype=">f4"),
            velocity_m_per_s=np.array(VELOCITY, dtype=">f8"),
            label=np.array(LABEL, dtype=">i4"),
            track_id=np.array(TRACK_ID, dtype=">i8"),
            score=np.array(SCORE, dtype=">f4"),
        )
    if layout == "narrow":
        return dict(
            translation_m=np.array(TRANSLATION, dtype="float16"),
            size=np.array(SIZE, dtype="float16"),
            yaw=np.array(YAW, dtype="float16"),
            velocity_m_per_s=np.array(VELOCITY, dtype="float16"),
            label=np.array(LABEL, dtype="int8"),
            track_id=np.array(TRACK_ID, dtype="uint16"),
            score=np.array(SCORE, dtype="float16"),
        )
    return dict(
        translation_m=np.array(TRANSLATION, dtype="float64"),
        size=np.array(SIZE, dtype="float32"),
        yaw=np.array(YAW, dtype="float32"),
        velocity_m_per_s=np.array(VELOCITY, dtype="float64"),
        label=np.array(LABEL, dtype="int32" if layout == "c_order" else "int16"),
        track_id=np.array(TRACK_ID, dtype="uint32" if layout == "object_strings" else "int32"),
        score=np.array(SCORE, dtype="float32"),
    )


def timestamp(i, layout):
    ts = T0 + i * 500_000_000
    if layout == "big_endian":
        return np.array(ts, dtype=">i8")[()]
    if layout == "narrow":
        return ts  # a plain Python int
    return np.int64(ts)


def submission():
    frames = []
    for i, layout in enumerate(LAYOUTS):
        frame = dict(seq_id=(LOG, PROMPT), timestamp_ns=timestamp(i, layout))
        frame["ego_translation_m"] = [1.0, 2.0, 3.0] if i % 2 else np.array([1.0, 2.0, 3.0])
        frame["description"] = PROMPT
        frame.update(arrays(layout))
        frame["name"] = strings(layout)
        frames.append(frame)
    return {(LOG, PROMPT): frames}


def tracks():
    frames = []
    for i, layout in enumerate(LAYOUTS):
        a = arrays(layout)
        frame = dict(timestamp_ns=timestamp(i, layout), name=strings(layout))
        for key in ("translation_m", "size", "yaw", "velocity_m_per_s", "track_id", "score"):
            frame[key] = a[key]
        frame["label"] = np.arange(len(NAME), dtype="int64")
        frames.append(frame)
    return {LOG: frames}


def expected():
    return dict(
        log_id=LOG,
        prompt=PROMPT,
        layouts=LAYOUTS,
        timestamps_ns=[T0 + i * 500_000_000 for i in range(len(LAYOUTS))],
        translation_m=TRANSLATION,
        size=SIZE,
        yaw=YAW,
        velocity_m_per_s=VELOCITY,
        name=NAME,
        label=LABEL,
        track_id=TRACK_ID,
        score=SCORE,
        ego_translation_m=[1.0, 2.0, 3.0],
    )


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    for protocol in range(6):
        for stem, obj in (("submission", submission()), ("tracks", tracks())):
            with open(os.path.join(out, f"{stem}_p{protocol}.pkl"), "wb") as f:
                pickle.dump(obj, f, protocol=protocol)
    with open(os.path.join(out, "expected.json"), "w") as f:
        json.dump(expected(), f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
