"""Reads a Rerun recording back with Rerun's own SDK (rerun-sdk, the crate's version) and prints
what is in it as JSON: per entity, whether it is static and its rows (frame, text, box labels,
box count). Used by tests/cli/rerun.rs; arguments: the .rrd file and the expected SDK version."""

import json
import sys

import rerun as rr
import rerun.experimental as ex

path, version = sys.argv[1], sys.argv[2]
if rr.__version__ != version:
    sys.exit(f"rerun-sdk {rr.__version__} is installed; the recording is written by {version}")
reader = ex.RrdReader(path)
out = {
    "recordings": [s.application_id for s in reader.recordings() if str(s.kind).endswith("recording")],
    "entities": {},
}


def column(batch, suffix):
    names = [n for n in batch.schema.names if n.endswith(suffix)]
    return batch.column(names[0]).to_pylist() if names else None


for chunk in reader.store().stream().to_chunks():
    batch = chunk.to_record_batch()
    entity = out["entities"].setdefault(
        chunk.entity_path, {"static": chunk.is_static, "rows": []}
    )
    frames = column(batch, "frame") if "frame" in batch.schema.names else None
    texts = column(batch, ":text")
    labels = column(batch, ":labels")
    centers = column(batch, ":centers")
    strips = column(batch, ":strips")
    for i in range(batch.num_rows):
        entity["rows"].append(
            {
                "frame": frames[i] if frames else None,
                "text": texts[i][0] if texts and texts[i] else None,
                "labels": labels[i] if labels else None,
                "boxes": len(centers[i]) if centers and centers[i] is not None else None,
                "strips": len(strips[i]) if strips and strips[i] is not None else None,
            }
        )
for entity in out["entities"].values():
    entity["rows"].sort(key=lambda r: -1 if r["frame"] is None else r["frame"])
json.dump(out, sys.stdout)
