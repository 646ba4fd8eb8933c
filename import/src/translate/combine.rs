//! Combining scenarios: `scenario_and` / `scenario_or`, the wrapped forms RefAV applies to a
//! function's result (`scenario_not`, `reverse_relationship`), and not-of-reversed.

use super::*;

impl Translator<'_> {
    pub(crate) fn combine(&mut self, and: bool, scens: &[Scen], hint: &str) -> Scen {
        let out = self.fresh(hint);
        if and {
            let body: Vec<String> = scens.iter().map(|s| format!("{}(X, T)", s.rel)).collect();
            self.emit(format!("{out}(X, T) :- {}.", body.join(", ")));
        } else {
            for s in scens {
                self.emit(format!("{out}(X, T) :- {}(X, T).", s.rel));
            }
        }
        let rs: Vec<&String> = scens.iter().filter_map(|s| s.rel_r.as_ref()).collect();
        let rel_r = if rs.is_empty() {
            None
        } else {
            for r in rs {
                self.emit(format!("{out}_r(X, Y, T) :- {out}(X, T), {r}(X, Y, T)."));
            }
            Some(format!("{out}_r"))
        };
        // RefAV's and / or keep the first scenario's keys in order, then (or) add the others':
        // one category's order only when every part follows it.
        let keys = scens.first().and_then(|s| s.keys.clone());
        let keys = keys.filter(|k| scens.iter().all(|s| s.keys.as_ref() == Some(k)));
        Scen {
            rel: out,
            rel_r,
            keys,
        }
    }

    pub(crate) fn apply_wrapped(
        &mut self,
        wrapper: &'static str,
        inner: &'static Signature,
        pos: Vec<Val>,
        kw: Vec<(String, Val)>,
        hint: Option<&str>,
    ) -> Res<Val> {
        if wrapper == "reverse_relationship" {
            if inner.kind != Kind::Relational {
                return Err(self.broken(
                    "reverse_relationship",
                    format!(
                        "reverse_relationship({})(...): the wrapper calls its function with (track_candidates, related_candidates, log_dir), which {}() does not take",
                        inner.name, inner.name
                    ),
                ));
            }
            let args = self.bind(inner, pos, kw)?;
            self.log_dir(inner.name, &args)?;
            let hint = hint.unwrap_or("reversed");
            if inner.name == "get_objects_in_relative_direction" {
                // RefAV special-cases this: the reverse is has_objects_in_relative_direction
                // (with get_objects' defaults, min_number 0).
                let (_, scen) = self.relational(inner, &args, hint, true)?;
                return Ok(Val::Scen(scen));
            }
            let (sel, _) = self.relational(inner, &args, &format!("{}_fwd", inner.name), false)?;
            let p0 = inner.params[0].0;
            let tracks = self.scen(inner.name, p0, args.get(p0).unwrap_or(&Val::None))?;
            let p1 = inner.params[1].0;
            let cands = self.scen(inner.name, p1, args.get(p1).unwrap_or(&Val::None))?;
            let keys = self.relation_keys(inner, &args, &tracks)?;
            let reversed = self.reverse(&sel, (&tracks, &cands), keys.as_deref(), hint);
            return Ok(Val::Scen(reversed));
        }
        // scenario_not
        let args = self.bind(inner, pos, kw)?;
        let base_param = if inner.name == "get_objects_in_relative_direction" {
            inner.params[1].0
        } else {
            inner.params[0].0
        };
        let base = self.scen(
            inner.name,
            base_param,
            args.get(base_param).unwrap_or(&Val::None),
        )?;
        let hint = hint.unwrap_or("not");
        // A filter whose body is one literal over X (and T) is negated in place.
        if inner.kind == Kind::Filter {
            let body = self.filter_body(inner.name, &args)?;
            self.log_dir(inner.name, &args)?;
            if let [lit] = body.as_slice() {
                if !lit.starts_with('!') && !lit.contains(" _") && !lit.contains("L)") {
                    let neg = format!("!{lit}");
                    return Ok(Val::Scen(self.filter(&base, &[neg], hint)));
                }
            }
        }
        let positive = match self.apply(inner, args, Some(&format!("{}_yes", inner.name)))? {
            Val::Scen(s) => s,
            _ => {
                return Err(self.err(
                    "scenario_not",
                    "the wrapped function gave no scenario".into(),
                ))
            }
        };
        let neg = format!("!{}(X, T)", positive.rel);
        Ok(Val::Scen(self.filter(&base, &[neg], hint)))
    }

    /// `scenario_not(reverse_relationship(f))(tracks, candidates, log_dir, …)`. RefAV's
    /// `scenario_not` finds `log_dir` among the parameters of `reverse_relationship`'s wrapper
    /// (`track_candidates, related_candidates, log_dir, …`), so the call must pass it third,
    /// positionally; the result is the tracks' pairs where the track is not itself a top-level
    /// object of the reversed relation (the reversal's top level is the candidates, so a track
    /// drops out only at frames where it is also a candidate `f` relates to some track).
    pub(crate) fn apply_not_reversed(
        &mut self,
        inner: &'static Signature,
        pos: Vec<Val>,
        kw: Vec<(String, Val)>,
        hint: Option<&str>,
    ) -> Res<Val> {
        if pos.len() < 3 {
            return Err(self.broken(
                "scenario_not",
                format!(
                    "IndexError: scenario_not(reverse_relationship({}))(...) reads log_dir as its third positional argument, and the call has {}",
                    inner.name,
                    pos.len()
                ),
            ));
        }
        let tracks = self.scen(inner.name, inner.params[0].0, &pos[0])?;
        let reversed = match self.apply_wrapped(
            "reverse_relationship",
            inner,
            pos,
            kw,
            Some(&format!("{}_reversed", inner.name)),
        )? {
            Val::Scen(s) => s,
            _ => {
                return Err(self.err(
                    "scenario_not",
                    "the wrapped function gave no scenario".into(),
                ))
            }
        };
        let neg = format!("!{}(X, T)", reversed.rel);
        Ok(Val::Scen(self.filter(
            &tracks,
            &[neg],
            hint.unwrap_or("not"),
        )))
    }
}
