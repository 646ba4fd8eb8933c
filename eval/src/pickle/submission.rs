//! The scenario-mining submission read from a parsed pickle: a dict of (log, prompt) sequences
//! of per-frame arrays into [`crate::Submission`], validated.

use super::*;

/// Reads a scenario-mining pickle from bytes; `what` names the source in errors.
pub fn read_pickle_bytes(data: &[u8], what: &str) -> Result<Submission, EvalError> {
    let pickle = parse_pickle_dict(data, what)?;
    let sub = Conv { pickle: &pickle }.submission(pickle.root)?;
    sub.validate(what)?;
    Ok(sub)
}

/// Reads a scenario-mining pickle file.
pub fn read_pickle(path: &std::path::Path) -> Result<Submission, EvalError> {
    let data = scenalog_input::read_file_checking_ends(
        path,
        scenalog_input::DATA_LIMIT,
        &super::dict_pickle_ends,
    )
    .map_err(|p| EvalError::File(path.display().to_string(), p))?;
    read_pickle_bytes(&data, &path.display().to_string())
}

pub(crate) struct Conv<'a> {
    pub(crate) pickle: &'a Pickle,
}

impl Conv<'_> {
    pub(crate) fn ferr(&self, place: &str, msg: impl std::fmt::Display) -> EvalError {
        EvalError::Format(format!("{}: {place}: {msg}", self.pickle.what))
    }

    pub(crate) fn node(&self, i: usize) -> Node<'_> {
        self.pickle.node(i)
    }

    pub(crate) fn submission(&self, root: usize) -> Result<Submission, EvalError> {
        let Obj::Dict(items) = &self.pickle.arena[root] else {
            return Err(self.ferr("top level", "expected a dict of (log_id, prompt) -> frames"));
        };
        let mut sequences = BTreeMap::new();
        for &(k, v) in items {
            let key = self.seq_key(k)?;
            let place = format!("sequence {key:?}");
            let Obj::List(frames) = &self.pickle.arena[v] else {
                return Err(self.ferr(&place, "expected a list of frames"));
            };
            let mut out = Vec::with_capacity(frames.len());
            for (i, &f) in frames.iter().enumerate() {
                out.push(self.frame(f, &format!("{place} frame {i}"))?);
            }
            if sequences.insert(key, out).is_some() {
                return Err(self.ferr(&place, "duplicate sequence"));
            }
        }
        Ok(Submission { sequences })
    }

    pub(crate) fn seq_key(&self, k: usize) -> Result<SeqKey, EvalError> {
        match &self.pickle.arena[k] {
            Obj::Tuple(v) if v.len() == 2 => {
                match (&self.pickle.arena[v[0]], &self.pickle.arena[v[1]]) {
                    (Obj::Str(a), Obj::Str(b)) => Ok((a.clone(), b.clone())),
                    _ => Err(self.ferr("sequence key", "expected (log_id, prompt) strings")),
                }
            }
            Obj::Str(s) => parse_seq_str(s)
                .ok_or_else(|| self.ferr("sequence key", format!("cannot parse {s:?}"))),
            _ => Err(self.ferr("sequence key", "expected a (log_id, prompt) tuple")),
        }
    }

    pub(crate) fn frame(&self, f: usize, place: &str) -> Result<FrameData, EvalError> {
        let Obj::Dict(items) = &self.pickle.arena[f] else {
            return Err(self.ferr(place, "expected a dict"));
        };
        let mut fr = FrameData::default();
        let mut n: Option<(usize, &'static str)> = None;
        let mut has_ts = false;
        for &(k, v) in items {
            let Obj::Str(key) = &self.pickle.arena[k] else {
                return Err(self.ferr(place, "non-string key"));
            };
            let fp = format!("{place} field {key:?}");
            let mut check = |len: usize, name: &'static str| -> Result<(), EvalError> {
                match n {
                    Some((m, other)) if m != len => {
                        Err(self.ferr(&fp, format!("has {len} objects but {other:?} has {m}")))
                    }
                    _ => {
                        n = Some((len, name));
                        Ok(())
                    }
                }
            };
            match key.as_str() {
                "timestamp_ns" => {
                    fr.timestamp_ns = self
                        .int(v)
                        .ok_or_else(|| self.ferr(&fp, "expected an integer"))?;
                    has_ts = true;
                }
                "ego_translation_m" => {
                    let vals = self
                        .float_list(v)
                        .ok_or_else(|| self.ferr(&fp, "expected 3 numbers"))?;
                    let [a, b, c] = vals.as_slice() else {
                        return Err(self.ferr(&fp, "expected 3 numbers"));
                    };
                    fr.ego_translation_m = [*a, *b, *c];
                }
                "description" => match &self.pickle.arena[v] {
                    Obj::Str(s) => fr.description = Some(s.clone()),
                    Obj::None => {}
                    _ => return Err(self.ferr(&fp, "expected a string")),
                },
                "is_positive" => {
                    fr.is_positive = Some(match &self.pickle.arena[v] {
                        Obj::None => None,
                        Obj::Bool(b) => Some(*b),
                        Obj::Int(i) => Some(*i != 0),
                        Obj::Scalar(d, b) if d.bare() == "b1" || d.bare() == "?" => {
                            Some(self.pickle.raw(*b).first().copied().unwrap_or(0) != 0)
                        }
                        _ => return Err(self.ferr(&fp, "expected True, False or None")),
                    })
                }
                "translation_m" | "velocity_m_per_s" => {
                    let a = self.num(v, &fp)?;
                    let rows = self.rows3(&a, &fp)?;
                    check(
                        rows.len(),
                        if key == "translation_m" {
                            "translation_m"
                        } else {
                            "velocity_m_per_s"
                        },
                    )?;
                    if key == "translation_m" {
                        fr.translation_m = rows;
                    } else {
                        fr.velocity_m_per_s = rows;
                    }
                }
                "size" => {
                    let a = self.num(v, &fp)?;
                    let rows = self.rows3(&a, &fp)?;
                    check(rows.len(), "size")?;
                    fr.size = rows
                        .iter()
                        .map(|r| [r[0] as f32, r[1] as f32, r[2] as f32])
                        .collect();
                }
                "yaw" | "score" => {
                    let a = self.num(v, &fp)?;
                    if a.shape.len() != 1 {
                        return Err(self.ferr(
                            &fp,
                            format!("expected a 1-d array, got shape {:?}", a.shape),
                        ));
                    }
                    check(a.values.len(), if key == "yaw" { "yaw" } else { "score" })?;
                    let v32: Vec<f32> = a.values.iter().map(|&x| x as f32).collect();
                    if key == "yaw" {
                        fr.yaw = v32;
                    } else {
                        fr.score = Some(v32);
                    }
                }
                "label" | "track_id" => {
                    let a = self.num(v, &fp)?;
                    if a.shape.len() != 1 {
                        return Err(self.ferr(
                            &fp,
                            format!("expected a 1-d array, got shape {:?}", a.shape),
                        ));
                    }
                    check(
                        a.values.len(),
                        if key == "label" { "label" } else { "track_id" },
                    )?;
                    let mut out = Vec::with_capacity(a.values.len());
                    for &x in &a.values {
                        if x.fract() != 0.0 || x < i32::MIN as f64 || x > i32::MAX as f64 {
                            return Err(
                                self.ferr(&fp, format!("value {x} is not a 32-bit integer"))
                            );
                        }
                        out.push(x as i32);
                    }
                    if key == "label" {
                        fr.label = out;
                    } else {
                        fr.track_id = out;
                    }
                }
                "name" => {
                    let names = self.strings(v, &fp)?;
                    check(names.len(), "name")?;
                    fr.name = names;
                }
                _ => {}
            }
        }
        if !has_ts {
            return Err(self.ferr(place, "missing field \"timestamp_ns\""));
        }
        if let Some((len, _)) = n {
            let checks: [(&str, usize); 6] = [
                ("translation_m", fr.translation_m.len()),
                ("size", fr.size.len()),
                ("yaw", fr.yaw.len()),
                ("label", fr.label.len()),
                ("name", fr.name.len()),
                ("track_id", fr.track_id.len()),
            ];
            for (name, l) in checks {
                if l != len {
                    return Err(self.ferr(
                        place,
                        format!("field {name:?} missing or of length {l}, expected {len}"),
                    ));
                }
            }
        }
        Ok(fr)
    }

    pub(crate) fn int(&self, v: usize) -> Option<i64> {
        match &self.pickle.arena[v] {
            Obj::Bool(_) => None,
            _ => self.node(v).int(),
        }
    }

    pub(crate) fn float_list(&self, v: usize) -> Option<Vec<f64>> {
        let node = self.node(v);
        if let Ok(a) = node.num_array() {
            return Some(a.values);
        }
        node.items()?.iter().map(|n| n.float()).collect()
    }

    pub(crate) fn num(&self, v: usize, fp: &str) -> Result<NumArray, EvalError> {
        self.node(v).num_array().map_err(|m| self.ferr(fp, m))
    }

    pub(crate) fn rows3(&self, a: &NumArray, fp: &str) -> Result<Vec<[f64; 3]>, EvalError> {
        match a.shape.as_slice() {
            [_, 3] => Ok(a.values.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()),
            [0] | [0, _] => Ok(Vec::new()),
            s => Err(self.ferr(fp, format!("expected shape (N, 3), got {s:?}"))),
        }
    }

    pub(crate) fn strings(&self, v: usize, fp: &str) -> Result<Vec<String>, EvalError> {
        self.node(v).str_array().map_err(|m| self.ferr(fp, m))
    }
}

/// Parses the string form "('log', 'prompt')" of a sequence key.
pub(crate) fn parse_seq_str(s: &str) -> Option<SeqKey> {
    let inner = s.strip_prefix("('")?.strip_suffix("')")?;
    let (a, b) = inner.split_once("', '")?;
    Some((a.to_string(), b.to_string()))
}
