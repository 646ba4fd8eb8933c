//! RefAV's filtering functions (categories, kinematics, map predicates) as the body of a
//! helper relation over (track, frame), and the helper that applies one to a scenario.

use super::*;

/// The start of the note an `is_color` program gets (once).
const COLOR_CACHE_NOTE: &str = "is_color reads RefAV's colour cache of each log";

impl Translator<'_> {
    pub(crate) fn category(&self, f: &str, v: &Val) -> Res<String> {
        match v {
            Val::Str(s)
                if scenalog_facts::scene::ALL_CATEGORIES.contains(&s.as_str())
                    || scenalog_facts::scene::SUPER_CATEGORIES.contains(&s.as_str()) =>
            {
                Ok(s.clone())
            }
            other => Err(self.err(
                f,
                format!(
                    "{f}(): category must be an AV2 category such as 'REGULAR_VEHICLE' (or 'VEHICLE', 'ANY'), got {} (RefAV would silently find nothing)",
                    match other {
                        Val::Str(s) => format!("'{s}'"),
                        o => o.kind_name().into(),
                    }
                ),
            )),
        }
    }

    /// Body literals over `X` and `T` for a filter function (RefAV's `@composable`).
    pub(crate) fn filter_body(
        &mut self,
        f: &str,
        args: &BTreeMap<&'static str, Val>,
    ) -> Res<Vec<String>> {
        let a = |k: &str| args.get(k).cloned().unwrap_or(Val::None);
        let range = |col: &str, lo: f64, hi: f64| {
            let mut v = Vec::new();
            if lo.is_finite() {
                v.push(format!("{col} >= {}", fmt_num(lo)));
            } else if lo == f64::INFINITY {
                v.push(format!("{col} > {col}"));
            }
            if hi.is_finite() {
                v.push(format!("{col} <= {}", fmt_num(hi)));
            } else if hi == f64::NEG_INFINITY {
                v.push(format!("{col} < {col}"));
            }
            v
        };
        Ok(match f {
            "is_category" => vec![format!(
                "category(X, \"{}\")",
                self.category(f, &a("category"))?
            )],
            "turning" | "changing_lanes" => {
                let rel = if f == "turning" && self.semantics.reproduces(Defect::TurningSpikes) {
                    "refav_turning"
                } else if f == "turning" && self.refav() {
                    "refav_turning_filtered"
                } else if f == "turning" {
                    "turning"
                } else if self.refav() {
                    "refav_lane_change"
                } else {
                    "lane_change"
                };
                // RefAV: any other direction prints a warning and means None.
                let dir = match a("direction") {
                    Val::Str(s) if s == "left" || s == "right" => format!("\"{s}\""),
                    _ => "_".to_string(),
                };
                vec![format!("{rel}(X, T, {dir})")]
            }
            "accelerating" if args.contains_key(signatures::FIRST_API_KEYWORD) => {
                // RefAV's first API (see `bind`): `min_accel = thresh`, no upper bound, and
                // its accelerating did not yet exclude stationary objects.
                let lo = self.num(
                    f,
                    signatures::FIRST_API_KEYWORD,
                    &a(signatures::FIRST_API_KEYWORD),
                )?;
                let mut v = vec!["accel(X, T, V)".to_string()];
                v.extend(range("V", lo, f64::INFINITY));
                v
            }
            "has_lateral_acceleration" | "accelerating" | "has_velocity" => {
                let (rel, lo, hi) = match f {
                    "has_lateral_acceleration" => ("lat_accel", "min_accel", "max_accel"),
                    "accelerating" => ("accel", "min_accel", "max_accel"),
                    _ => ("speed", "min_velocity", "max_velocity"),
                };
                let lo = self.num(f, lo, &a(lo))?;
                let hi = self.num(f, hi, &a(hi))?;
                let mut v = vec![format!("{rel}(X, T, V)")];
                v.extend(range("V", lo, hi));
                // RefAV returns nothing for a stationary (parked) object in these three.
                v.push("!stationary(X)".into());
                v
            }
            "at_pedestrian_crossing" => {
                let d = self.num(f, "within_distance", &a("within_distance"))?;
                if self.refav() {
                    if self.semantics.reproduces(Defect::CrosswalkLoop) {
                        return Ok(vec![format!("{}(X, T)", self.crosswalk_loop(d))]);
                    }
                    let mut v = vec!["refav_crosswalk(X, T, _, D)".to_string()];
                    v.extend(range("D", f64::NEG_INFINITY, d));
                    return Ok(v);
                }
                // RefAV's default distance is the prelude's meaning of "at a crosswalk".
                if d == AT_A_CROSSWALK_M {
                    return Ok(vec!["at_a_crosswalk(X, T)".to_string()]);
                }
                let mut v = vec!["at_crosswalk(X, T, D)".to_string()];
                v.extend(range("D", f64::NEG_INFINITY, d));
                v
            }
            "is_color" => {
                // RefAV keeps an object unless the log's colour cache holds it with `null` or
                // another colour (`scenalog_facts::color`): no cache, or a track it lacks,
                // keeps everything.
                let h = self.fresh("is_color_other");
                match a("color") {
                    Val::Str(c) if scenalog_facts::color::REFAV_COLORS.contains(&c.as_str()) => {
                        self.emit(format!(
                            "{h}(X) :- refav_color(X, C), C != \"{c}\"."
                        ));
                    }
                    Val::Str(c) if c.chars().all(|ch| ch.is_ascii_alphanumeric()) => {
                        self.notes.push(format!(
                            "is_color(color='{c}'): not one of RefAV's colours ({}); RefAV's code then drops every object its colour cache holds (its docstring says it keeps all)",
                            scenalog_facts::color::REFAV_COLORS.join(", ")
                        ));
                        self.emit(format!("{h}(X) :- refav_color(X, _)."));
                    }
                    other => {
                        return Err(self.err(
                            f,
                            format!(
                                "is_color()'s argument 'color' is {}; it must be a colour word such as 'red'",
                                match other {
                                    Val::Str(s) => format!("'{s}'"),
                                    o => o.kind_name().to_string(),
                                }
                            ),
                        ))
                    }
                }
                if !self.notes.iter().any(|n| n.starts_with(COLOR_CACHE_NOTE)) {
                    self.notes.push(format!(
                        "{COLOR_CACHE_NOTE} (`{}`, written by RefAV's construct_caches); a log without one keeps every object, as RefAV does, and mine says so once per log",
                        scenalog_facts::color::COLOR_CACHE_FILE
                    ));
                }
                vec![format!("!{h}(X)")]
            }
            "on_lane_type" => {
                let ty = self.word(f, "lane_type", &a("lane_type"), catalog::LANE_TYPES, false)?;
                vec![
                    format!("in_lane(X, T, L)"),
                    format!("lane_type(L, \"{}\")", ty.unwrap_or_default()),
                ]
            }
            "near_intersection" => {
                let d = self.num(f, "threshold", &a("threshold"))?;
                let mut v = vec!["near_intersection(X, T, D)".to_string()];
                v.extend(range("D", f64::NEG_INFINITY, d));
                v
            }
            "on_intersection" if self.refav() => vec!["refav_on_intersection(X, T)".into()],
            "on_intersection" => vec!["on_intersection(X, T)".into()],
            "stationary" => vec!["stationary(X)".into()],
            "in_drivable_area" => vec!["in_drivable_area(X, T)".into()],
            "on_road" => vec!["on_road(X, T)".into()],
            "at_stop_sign" => {
                let d = self.num(f, "forward_thresh", &a("forward_thresh"))?;
                if d != 10.0 {
                    return Err(self.err(
                        f,
                        format!("at_stop_sign(forward_thresh={}) : the catalog's at_stop_sign fixes 10 m", fmt_num(d)),
                    ));
                }
                vec!["at_stop_sign(X, _, T)".into()]
            }
            _ => return Err(self.err(f, format!("{f}() is not a filter"))),
        })
    }

    /// RefAV's `at_pedestrian_crossing(within_distance=d)` with its loop defect, as a relation
    /// over (track, frame): at a track's first frame every crossing is tested (dilated by `d`);
    /// at each later frame only those its box overlapped at the frame before, and none once it
    /// overlapped none (RefAV's list stays empty). Over every frame of the track, as RefAV's.
    fn crosswalk_loop(&mut self, d: f64) -> String {
        let frames = self.crosswalk_frames();
        let h = self.fresh("at_pedestrian_crossing_loop");
        let within = format!("D <= {}", fmt_num(d));
        self.emit(format!(
            "{h}(X, T) :- {frames}_first(X, T), refav_crosswalk(X, T, _, D), {within}."
        ));
        self.emit(format!(
            "{h}(X, T) :- {frames}_prev(X, T, P), {frames}_live(X, P), refav_crosswalk(X, P, C, D0), D0 <= 0.0, refav_crosswalk(X, T, C, D), {within}."
        ));
        h
    }

    /// The helpers every use of [`Self::crosswalk_loop`] shares, emitted once a program: each
    /// object's frame before a frame (`_prev`), its first frame (`_first`), and the frames at
    /// which RefAV's list of crossings is not yet empty (`_live`), whatever the distance.
    fn crosswalk_frames(&mut self) -> String {
        if let Some(h) = &self.crosswalk_frames {
            return h.clone();
        }
        let h = self.fresh("crosswalk_loop_frames");
        for part in ["prev", "gap", "later", "first", "live"] {
            self.used_names.insert(format!("{h}_{part}"));
        }
        // The frame before T in X's track: T - 0.1 s at 10 Hz, else (a gap, a slower rate, the first
        // frame) the latest earlier one, if any.
        self.emit(format!(
            "{h}_prev(X, T, P) :- present(X, T), P = T - 0.1 s, present(X, P)."
        ));
        self.emit(format!(
            "{h}_gap(X, T) :- present(X, T), P = T - 0.1 s, !present(X, P)."
        ));
        self.emit(format!(
            "{h}_prev(X, T, P) :- {h}_gap(X, T), P = max U : {{ present(X, U), U < T }}."
        ));
        self.emit(format!("{h}_later(X, T) :- {h}_prev(X, T, _)."));
        self.emit(format!(
            "{h}_first(X, T) :- present(X, T), !{h}_later(X, T)."
        ));
        self.emit(format!("{h}_live(X, T) :- {h}_first(X, T)."));
        self.emit(format!(
            "{h}_live(X, T) :- {h}_prev(X, T, P), {h}_live(X, P), refav_crosswalk(X, P, _, D0), D0 <= 0.0."
        ));
        self.crosswalk_frames = Some(h.clone());
        h
    }

    pub(crate) fn filter(&mut self, input: &Scen, body: &[String], hint: &str) -> Scen {
        let out = self.fresh(hint);
        self.emit(format!(
            "{out}(X, T) :- {}(X, T), {}.",
            input.rel,
            body.join(", ")
        ));
        let rel_r = input.rel_r.as_ref().map(|r| {
            let out_r = format!("{out}_r");
            self.emit(format!("{out_r}(X, Y, T) :- {out}(X, T), {r}(X, Y, T)."));
            out_r
        });
        Scen {
            rel: out,
            rel_r,
            keys: input.keys.clone(),
        }
    }
}
