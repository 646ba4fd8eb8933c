//! RefAV's relational functions (objects in a relative direction, crossings, following, …)
//! as helper relations over (track, related, frame), their counts, and reversing a relation.

use super::*;

/// Where a relational function is computed: at the frames of its scenarios (the function's
/// meaning), or at every frame the two objects share (RefAV's own computation, before it keeps
/// the scenarios' frames).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Frames {
    Scenario,
    Shared,
}

impl Translator<'_> {
    /// The box-to-box distance relation: RefAV's (the ego at its rear axle) in refav mode.
    fn near_relation(&self) -> &'static str {
        if self.refav() {
            "refav_near"
        } else {
            "near"
        }
    }

    /// A relational function: its selected (track, candidate, frame) pairs, and its result.
    pub(crate) fn relational(
        &mut self,
        sig: &'static Signature,
        args: &BTreeMap<&'static str, Val>,
        hint: &str,
        want_result: bool,
    ) -> Res<(String, Scen)> {
        self.relational_at(sig, args, hint, want_result, Frames::Scenario)
    }

    /// [`Self::relational`] computed at `frames`.
    fn relational_at(
        &mut self,
        sig: &'static Signature,
        args: &BTreeMap<&'static str, Val>,
        hint: &str,
        want_result: bool,
        frames: Frames,
    ) -> Res<(String, Scen)> {
        let f = sig.name;
        let a = |k: &str| args.get(k).cloned().unwrap_or(Val::None);
        let tracks = self.scen(f, sig.params[0].0, &a(sig.params[0].0))?;
        let cands = self.scen(f, sig.params[1].0, &a(sig.params[1].0))?;
        // RefAV computes the relation at every frame both objects share; the scenarios' frames
        // only filter it afterwards ([`Self::relation_keys`]).
        let out = self.fresh(hint);
        let (x_at, y_at) = if frames == Frames::Shared {
            // The scenarios' objects, whatever the frame.
            let (tk, ck) = (self.keys_of(&tracks), self.keys_of(&cands));
            (format!("{tk}(X)"), format!("{ck}(Y)"))
        } else {
            (
                format!("{}(X, T)", tracks.rel),
                format!("{}(Y, T)", cands.rel),
            )
        };
        let base = format!("{x_at}, {y_at}, X != Y");
        let pairs = format!("{out}_pairs");
        self.used_names.insert(pairs.clone());
        let mut min_count = 1.0;
        match f {
            "has_objects_in_relative_direction" | "get_objects_in_relative_direction" => {
                let dir = self
                    .word(f, "direction", &a("direction"), catalog::DIRECTIONS, false)?
                    .unwrap_or_default();
                let min = self.num(f, "min_number", &a("min_number"))?;
                let max = self.num(f, "max_number", &a("max_number"))?;
                let within = self.num(f, "within_distance", &a("within_distance"))?;
                let lat = self.num(f, "lateral_thresh", &a("lateral_thresh"))?;
                if within > 50.0 {
                    self.notes.push(format!(
                        "line {}: within_distance={} is capped at 50 m, the range of the catalog's pair relations",
                        self.line,
                        fmt_num(within)
                    ));
                }
                // RefAV counts the closest candidates within the distance, up to max_number;
                // a timestamp with no candidate is never kept, so min_number 0 means 1.
                min_count = min.max(1.0).ceil();
                if max < min_count {
                    return Err(self.err(
                        f,
                        format!(
                            "{f}(min_number={}, max_number={}) can never hold",
                            fmt_num(min),
                            fmt_num(max)
                        ),
                    ));
                }
                let cand = format!("{out}_cand");
                self.used_names.insert(cand.clone());
                let rel = match self.semantics {
                    Semantics::Scenalog => "direction",
                    s if s.reproduces(Defect::EgoBackEdge) => "refav_direction",
                    Semantics::Refav(_) => "refav_direction_corrected",
                };
                let mut conds = vec![format!("{rel}(X, Y, T, \"{dir}\", D, Lat)")];
                if within.is_finite() {
                    conds.push(format!("D <= {}", fmt_num(within)));
                }
                if lat.is_finite() {
                    conds.push(format!("Lat < {}", fmt_num(lat)));
                }
                self.emit(format!(
                    "{cand}(X, Y, T, D) :- {base}, {}.",
                    conds.join(", ")
                ));
                if max.is_finite() {
                    // the max_number closest (ties: RefAV's stable sort keeps the earlier one;
                    // here every tied candidate is kept)
                    self.emit(format!(
                        "{pairs}(X, Y, T) :- {cand}(X, Y, T, D), R = count : {{ {cand}(X, Y2, T, D2), D2 < D }}, R < {}.",
                        max as i64
                    ));
                } else {
                    self.emit(format!("{pairs}(X, Y, T) :- {cand}(X, Y, T, _)."));
                }
            }
            "near_objects" => {
                let d = self.num(f, "distance_thresh", &a("distance_thresh"))?;
                let min = match a("min_objects") {
                    Val::None => 0.0,
                    v => self.num(f, "min_objects", &v)?,
                };
                if min <= 0.0 {
                    return Err(self.err(
                        f,
                        "near_objects(min_objects=0) means \"all candidates\", a count Scenalog does not translate".into(),
                    ));
                }
                min_count = min.ceil();
                let include_self = matches!(a("include_self"), Val::Bool(true));
                let base = if include_self {
                    format!("{x_at}, {y_at}")
                } else {
                    base.clone()
                };
                self.emit(format!(
                    "{pairs}(X, Y, T) :- {base}, {}(X, Y, T, D), D <= {}.",
                    self.near_relation(),
                    fmt_num(d)
                ));
            }
            "being_crossed_by" => {
                let dir = self
                    .word(f, "direction", &a("direction"), catalog::DIRECTIONS, false)?
                    .unwrap_or_default();
                let in_dir = self
                    .word(
                        f,
                        "in_direction",
                        &a("in_direction"),
                        &["clockwise", "counterclockwise", "either"],
                        false,
                    )?
                    .unwrap_or_default();
                let fwd = self.num(f, "forward_thresh", &a("forward_thresh"))?;
                let lat = self.num(f, "lateral_thresh", &a("lateral_thresh"))?;
                let sense = match in_dir.as_str() {
                    "either" => "_".to_string(),
                    s => format!("\"{s}\""),
                };
                if self.refav() {
                    self.refav_crossing(&pairs, &base, (&tracks, &cands), &dir, &sense, [fwd, lat]);
                } else if in_dir == "either" && fwd == 10.0 && lat == 5.0 {
                    self.emit(format!(
                        "{pairs}(X, Y, T) :- {base}, crossing(X, Y, T, \"{dir}\")."
                    ));
                } else {
                    if !(0.0..=CROSSING_MAX_REACH).contains(&fwd)
                        || !(0.0..=CROSSING_MAX_OFF).contains(&lat)
                    {
                        return Err(self.err(
                            f,
                            format!(
                                "being_crossed_by(forward_thresh={}, lateral_thresh={}): crossing_detail covers 0-{} m and 0-{} m",
                                fmt_num(fwd),
                                fmt_num(lat),
                                fmt_num(CROSSING_MAX_REACH),
                                fmt_num(CROSSING_MAX_OFF)
                            ),
                        ));
                    }
                    self.emit(format!(
                        "{pairs}(X, Y, T) :- {base}, crossing_detail(X, Y, T, \"{dir}\", {sense}, Reach, Off), Reach <= {}, Off <= {}.",
                        fmt_num(fwd),
                        fmt_num(lat)
                    ));
                }
            }
            "facing_toward" => {
                let ang = self.num(f, "within_angle", &a("within_angle"))?;
                let d = self.num(f, "max_distance", &a("max_distance"))?;
                if ang != 22.5 {
                    return Err(self.err(
                        f,
                        format!(
                            "facing_toward(within_angle={}): the catalog's facing fixes 22.5°",
                            fmt_num(ang)
                        ),
                    ));
                }
                let mut c = format!("{pairs}(X, Y, T) :- {base}, facing(X, Y, T)");
                if d.is_finite() {
                    c.push_str(&format!(
                        ", {}(X, Y, T, D), D <= {}",
                        self.near_relation(),
                        fmt_num(d)
                    ));
                }
                self.emit(c + ".");
            }
            "heading_toward" => {
                let ang = self.num(f, "angle_threshold", &a("angle_threshold"))?;
                let sp = self.num(f, "minimum_speed", &a("minimum_speed"))?;
                let d = self.num(f, "max_distance", &a("max_distance"))?;
                if ang != 22.5 || sp != 0.5 {
                    return Err(self.err(f, format!("heading_toward(angle_threshold={}, minimum_speed={}): the catalog's heading_toward fixes 22.5° and 0.5 m/s", fmt_num(ang), fmt_num(sp))));
                }
                let mut c = format!("{pairs}(X, Y, T) :- {base}, heading_toward(X, Y, T)");
                if d.is_finite() {
                    c.push_str(&format!(
                        ", {}(X, Y, T, D), D <= {}",
                        self.near_relation(),
                        fmt_num(d)
                    ));
                }
                self.emit(c + ".");
            }
            "following" => self.emit(format!("{pairs}(X, Y, T) :- {base}, following(X, Y, T).")),
            "in_same_lane" => self.emit(format!("{pairs}(X, Y, T) :- {base}, same_lane(X, Y, T).")),
            "heading_in_relative_direction_to" => {
                let d = self
                    .word(f, "direction", &a("direction"), catalog::HEADINGS, false)?
                    .unwrap_or_default();
                self.emit(format!(
                    "{pairs}(X, Y, T) :- {base}, heading_relative(X, Y, T, \"{d}\")."
                ));
            }
            "on_relative_side_of_road" => {
                let s = self
                    .word(f, "side", &a("side"), catalog::ROAD_SIDES, false)?
                    .unwrap_or_default();
                self.emit(format!(
                    "{pairs}(X, Y, T) :- {base}, road_side(X, Y, T, \"{s}\")."
                ));
            }
            _ => return Err(self.err(f, format!("{f}() is not a relational function"))),
        }
        // Tracks with at least `min_count` related candidates at the frame; only the pairs at
        // kept frames are the function's relationships (RefAV applies `min_number` before it
        // creates any, so `get_objects_in_relative_direction` keeps it too).
        let sel = if min_count > 1.0 {
            let at = if frames == Frames::Shared {
                format!("{pairs}(X, _, T)")
            } else {
                format!("{}(X, T)", tracks.rel)
            };
            self.emit(format!(
                "{out}(X, T) :- {at}, N = count : {{ {pairs}(X, Y2, T) }}, N >= {}.",
                min_count as i64
            ));
            let sel = format!("{out}_sel");
            self.used_names.insert(sel.clone());
            self.emit(format!("{sel}(X, Y, T) :- {out}(X, T), {pairs}(X, Y, T)."));
            sel
        } else {
            if want_result {
                self.emit(format!("{out}(X, T) :- {pairs}(X, _, T)."));
            }
            pairs
        };
        if !want_result {
            return Ok((
                sel,
                Scen {
                    rel: out,
                    rel_r: None,
                    keys: tracks.keys.clone(),
                },
            ));
        }
        self.finish_relational(&out, &sel, &tracks, &cands)
    }

    pub(crate) fn finish_relational(
        &mut self,
        out: &str,
        sel: &str,
        tracks: &Scen,
        cands: &Scen,
    ) -> Res<(String, Scen)> {
        let out_r = format!("{out}_r");
        self.emit(format!("{out_r}(X, Y, T) :- {sel}(X, Y, T)."));
        if let Some(r) = &tracks.rel_r {
            self.emit(format!("{out_r}(X, Z, T) :- {out}(X, T), {r}(X, Z, T)."));
        }
        if let Some(r) = &cands.rel_r {
            self.emit(format!("{out_r}(X, Z, T) :- {sel}(X, Y, T), {r}(Y, Z, T)."));
        }
        Ok((
            sel.to_string(),
            Scen {
                rel: out.to_string(),
                rel_r: Some(out_r),
                keys: tracks.keys.clone(),
            },
        ))
    }

    /// The (track, candidate) pairs a relational function relates at any frame the two share,
    /// whatever the scenarios' frames: the keys RefAV's `composable_relational` gives a track
    /// before it keeps the scenario's frames, which decide its `reverse_relationship`'s
    /// bookkeeping (the carry-over defect). `None` unless that defect is reproduced.
    pub(crate) fn relation_keys(
        &mut self,
        sig: &'static Signature,
        args: &BTreeMap<&'static str, Val>,
        tracks: &Scen,
    ) -> Res<Option<String>> {
        if tracks.rel_r.is_none() || !self.semantics.reproduces(Defect::ReverseCarryOver) {
            return Ok(None);
        }
        let notes = self.notes.len();
        let hint = format!("{}_any_frame", sig.name);
        let result = self.relational_at(sig, args, &hint, false, Frames::Shared);
        self.notes.truncate(notes);
        let (sel, _) = result?;
        let keys = format!("{sel}_keys");
        self.used_names.insert(keys.clone());
        self.emit(format!("{keys}(X, Y) :- {sel}(X, Y, _)."));
        Ok(Some(keys))
    }

    /// `being_crossed_by` in RefAV's definitions. With the `crossing-direction` defect and a
    /// direction other than "forward", RefAV's loop over a track's candidates (in
    /// `refav_order`) uses the direction until the first candidate it finds crossing the track
    /// (`refav_crossing_event`), and the forward plane for every later one.
    fn refav_crossing(
        &mut self,
        pairs: &str,
        base: &str,
        (tracks, cands): (&Scen, &Scen),
        dir: &str,
        sense: &str,
        [fwd, lat]: [f64; 2],
    ) {
        let (fwd_s, lat_s) = (fmt_num(fwd), fmt_num(lat));
        let span = |d: &str| {
            format!(
                "refav_crossing(X, Y, T, \"{d}\", {sense}, Reach, Off), Reach <= {fwd_s}, Off < {lat_s}"
            )
        };
        if dir == "forward" || !self.semantics.reproduces(Defect::CrossingDirection) {
            self.emit(format!("{pairs}(X, Y, T) :- {base}, {}.", span(dir)));
            return;
        }
        let cat = match &cands.keys {
            Some(k) => k.clone(),
            None => {
                self.notes.push(format!(
                    "line {}: being_crossed_by's candidates mix categories; RefAV's order of them is taken as get_objects_of_category(\"ANY\")'s (the annotation file's)",
                    self.line
                ));
                "ANY".to_string()
            }
        };
        let (tk, ck) = (self.keys_of(tracks), self.keys_of(cands));
        let first = format!("{pairs}_first");
        let late = format!("{pairs}_late");
        self.used_names.insert(first.clone());
        self.used_names.insert(late.clone());
        self.emit(format!(
            "{first}(X, R0) :- {tk}(X), R0 = min R : {{ {ck}(Y), refav_crossing_event(X, Y, _, \"{dir}\", E), E <= {fwd_s}, refav_order(Y, \"{cat}\", R) }}."
        ));
        self.emit(format!(
            "{late}(X, Y) :- {first}(X, R0), {ck}(Y), refav_order(Y, \"{cat}\", R), R > R0."
        ));
        self.emit(format!(
            "{pairs}(X, Y, T) :- {base}, {}, !{late}(X, Y).",
            span(dir)
        ));
        self.emit(format!(
            "{pairs}(X, Y, T) :- {base}, {}, {late}(X, Y).",
            span("forward")
        ));
    }

    /// The candidates of a relational result become the tracks, and its tracks their related.
    /// As in RefAV, a track's own related objects at the frame come along under it (RefAV nests
    /// them under the reversed relation), except those the function itself related it to; the
    /// candidates' related objects do not. With the `reverse-carry-over` defect, a track's earlier
    /// related objects that are among the candidates (or, for a track that is a candidate too,
    /// among the tracks) are RefAV's "new relationships" too: they become tracks at the frames of
    /// the earlier relation where the function relates the track to something.
    pub(crate) fn reverse(
        &mut self,
        pairs: &str,
        (tracks, cands): (&Scen, &Scen),
        keys: Option<&str>,
        hint: &str,
    ) -> Scen {
        let out = self.fresh(hint);
        let carry = self.semantics.reproduces(Defect::ReverseCarryOver);
        let all = match &tracks.rel_r {
            Some(r) if carry => {
                let all = format!("{out}_all");
                self.used_names.insert(all.clone());
                let own = match keys {
                    Some(k) => k.to_string(),
                    None => {
                        let own = format!("{out}_own");
                        self.used_names.insert(own.clone());
                        self.emit(format!("{own}(X, Y) :- {pairs}(X, Y, _)."));
                        own
                    }
                };
                let (tk, ck) = (self.keys_of(tracks), self.keys_of(cands));
                self.emit(format!("{all}(X, Y, T) :- {pairs}(X, Y, T)."));
                self.emit(format!(
                    "{all}(X, Z, T) :- {r}(X, Z, T), {pairs}(X, _, T), {ck}(Z), !{own}(X, Z)."
                ));
                self.emit(format!(
                    "{all}(X, Z, T) :- {r}(X, Z, T), {pairs}(X, _, T), {ck}(X), {tk}(Z), X != Z, !{own}(X, Z)."
                ));
                all
            }
            _ => pairs.to_string(),
        };
        self.emit(format!("{out}(Y, T) :- {all}(_, Y, T)."));
        self.emit(format!("{out}_r(Y, X, T) :- {all}(X, Y, T)."));
        if let Some(r) = &tracks.rel_r {
            let new = format!("{out}_new");
            self.used_names.insert(new.clone());
            self.emit(format!("{new}(X, Y) :- {all}(X, Y, _)."));
            // With the carry-over, RefAV drops an earlier related object the function relates
            // to the track only at frames outside the track's scenario (its entry is emptied).
            let dropped = match keys {
                Some(k) if carry => format!(", !{k}(X, Z)"),
                _ => String::new(),
            };
            self.emit(format!(
                "{out}_r(Y, Z, T) :- {all}(X, Y, T), {r}(X, Z, T), Z != Y, !{new}(X, Z){dropped}."
            ));
        }
        Scen {
            rel: out.clone(),
            rel_r: Some(format!("{out}_r")),
            keys: cands.keys.clone(),
        }
    }
}
