//! One frame of a tracker's output, decoded and validated.

use scenalog_eval::Node;
use scenalog_facts::scene::ALL_CATEGORIES;

use crate::error::TrackerError;

/// The detections of one frame of one log, every array of the same length, every number finite.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Detections {
    /// The frame's timestamp (ns).
    pub timestamp_ns: i64,
    /// Box centres, city frame (m).
    pub translation_m: Vec<[f64; 3]>,
    /// Length, width, height (m), each > 0.
    pub size: Vec<[f64; 3]>,
    /// Headings about the city z axis (rad).
    pub yaw: Vec<f64>,
    /// AV2 category names.
    pub name: Vec<String>,
    /// Confidence scores.
    pub score: Vec<f32>,
    /// Integer track ids (unique within the frame).
    pub track_id: Vec<i64>,
}

impl Detections {
    /// The number of boxes.
    pub fn len(&self) -> usize {
        self.track_id.len()
    }

    /// Whether the frame has no box.
    pub fn is_empty(&self) -> bool {
        self.track_id.is_empty()
    }
}

/// The fields every tracking frame must have.
pub const REQUIRED_FIELDS: &[&str] = &[
    "timestamp_ns",
    "translation_m",
    "size",
    "yaw",
    "name",
    "score",
    "track_id",
];

/// Decodes one frame dict. `file`, `log` and `index` name the frame in errors.
pub fn decode_frame(
    node: Node<'_>,
    file: &str,
    log: &str,
    index: usize,
) -> Result<Detections, TrackerError> {
    let err = |field: &str, m: String| TrackerError::field(file, log, index, field, m);
    let items = node.dict().ok_or_else(|| TrackerError {
        frame: Some(index),
        ..TrackerError::log(
            file,
            log,
            format!("expected a frame dict, got a {}", node.kind()),
        )
    })?;
    let get = |name: &str| {
        items
            .iter()
            .find(|(k, _)| k.str() == Some(name))
            .map(|(_, v)| *v)
            .ok_or_else(|| err(name, "missing (not the 3D-tracking format?)".into()))
    };
    let mut d = Detections {
        timestamp_ns: get("timestamp_ns")?
            .int()
            .ok_or_else(|| err("timestamp_ns", "expected an integer".into()))?,
        ..Detections::default()
    };
    let rows3 = |field: &str| -> Result<Vec<[f64; 3]>, TrackerError> {
        let a = get(field)?.num_array().map_err(|m| err(field, m))?;
        match a.shape.as_slice() {
            [_, 3] => Ok(a.values.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()),
            [0] | [0, _] => Ok(Vec::new()),
            s => Err(err(field, format!("expected shape (N, 3), got {s:?}"))),
        }
    };
    let flat = |field: &str| -> Result<Vec<f64>, TrackerError> {
        let a = get(field)?.num_array().map_err(|m| err(field, m))?;
        if a.shape.len() != 1 {
            return Err(err(
                field,
                format!("expected shape (N,), got {:?}", a.shape),
            ));
        }
        Ok(a.values)
    };
    d.translation_m = rows3("translation_m")?;
    d.size = rows3("size")?;
    d.yaw = flat("yaw")?;
    d.score = flat("score")?.into_iter().map(|s| s as f32).collect();
    let ids = get("track_id")?
        .num_array()
        .map_err(|m| err("track_id", m))?;
    if ids.dtype.starts_with('f') {
        return Err(err(
            "track_id",
            format!("expected integers, got dtype {}", ids.dtype),
        ));
    }
    if ids.shape.len() != 1 {
        return Err(err(
            "track_id",
            format!("expected shape (N,), got {:?}", ids.shape),
        ));
    }
    d.track_id = ids.values.iter().map(|&x| x as i64).collect();
    d.name = get("name")?.str_array().map_err(|m| err("name", m))?;

    let n = d.track_id.len();
    for (field, len) in [
        ("translation_m", d.translation_m.len()),
        ("size", d.size.len()),
        ("yaw", d.yaw.len()),
        ("score", d.score.len()),
        ("name", d.name.len()),
    ] {
        if len != n {
            return Err(err(field, format!("{len} values but \"track_id\" has {n}")));
        }
    }
    for i in 0..n {
        let at = |what: &str| format!("box {i} (track {}): {what}", d.track_id[i]);
        if d.translation_m[i].iter().any(|v| !v.is_finite()) {
            return Err(err(
                "translation_m",
                at(&format!("not finite: {:?}", d.translation_m[i])),
            ));
        }
        if d.size[i].iter().any(|v| !v.is_finite() || *v <= 0.0) {
            return Err(err(
                "size",
                at(&format!("not finite and positive: {:?}", d.size[i])),
            ));
        }
        if !d.yaw[i].is_finite() {
            return Err(err("yaw", at(&format!("not finite: {}", d.yaw[i]))));
        }
        if !d.score[i].is_finite() {
            return Err(err("score", at(&format!("not finite: {}", d.score[i]))));
        }
        if !ALL_CATEGORIES.contains(&d.name[i].as_str()) || d.name[i] == "EGO_VEHICLE" {
            return Err(err(
                "name",
                at(&format!("unknown AV2 category {:?}", d.name[i])),
            ));
        }
    }
    let mut seen = std::collections::HashSet::with_capacity(n);
    if let Some(dup) = d.track_id.iter().find(|t| !seen.insert(**t)) {
        return Err(err(
            "track_id",
            format!("track {dup} appears twice in the frame"),
        ));
    }
    Ok(d)
}
