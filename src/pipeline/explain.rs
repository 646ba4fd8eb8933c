//! Explanations of a scenario on one log, for `scenalog explain`: the evaluation they need,
//! the grounded proof of `referred(track, frame)` and the why-not report, rendered for people
//! (values in readable form: tracks as uuid prefix and category, frames as seconds from the
//! log's start, lanes with their type, numbers with their unit) and as JSON for tools.
//!
//! # JSON
//!
//! [`explanation_json`] returns one object with these keys (stable; new keys may be added):
//!
//! - `log_id`, `rules` (the program file), `description`
//! - `track`: `{uuid, category}`; `frame` (frame index), `seconds` (from the log's start)
//! - `referred` (bool: is `referred(track, frame)` derived), `referred_frames` (how many frames
//!   the track is referred in), `referred_seconds` (`[first, last]` or `null`)
//! - `proof`: a derivation or `null`; a derivation is `{relation, tuple, text, clause, binding,
//!   body}` where `clause` is `null` for a catalog fact, else `{index, line, text}` (the rule's
//!   source); `binding` maps variable names to values; `body` lists one entry per body literal in
//!   source order: `{literal, source, kind, text, …}` with `kind` one of `"atom"` (`relation`,
//!   `tuple`, `derivation`: a nested derivation or `null`), `"absent"` (`relation`, `pattern`),
//!   `"comparison"` (`lhs`, `op`, `rhs`, `binds`), `"aggregate"` (`func`, `result`,
//!   `group_size`)
//! - `why_not`: a report or `null` (present with `--why-not` or when the track is not referred
//!   there): `{relation, pattern, holds, input, relation_size, closest_input, closest_clause,
//!   attempts}`; each attempt is `{clause: {index, line, text}, outcome, …}` with `outcome`
//!   `"derives"` (`binding`, `bindings`), `"head_mismatch"` (`column`, `expected`, `found`) or
//!   `"fails"` (`failure`: `{step: {"body": i} | {"head": i}, literal, held, bindings,
//!   binding_count, truncated, reason}`); `reason` is `{kind, text, …}` with `kind` one of
//!   `"missing"` (`relation`, `relation_size`, `wanted`, `closest`: `[{tuple, differs}]`,
//!   `nested`: a report or `null`), `"comparison"` (`op`, `values`: `[{binding, lhs, rhs}]`),
//!   `"present"` (`relation`, `found`: `[{binding, tuple}]`), `"aggregate"` (`func`, `values`:
//!   `[{binding, result, required, group_size}]`), `"head_value"` (`column`, `wanted`,
//!   `values`: `[{binding, value}]`), `"unevaluable"`
//!
//! Values are as in `scenalog facts --json`: tracks as uuids, lanes as map ids, times as frame
//! indices, strings and numbers as themselves; every entry with a `text` key also has the
//! human rendering.

use scenalog_engine::{
    BodyFact, ClauseAttempt, Derivation, EngineError, Evaluation, Failure, Options, Outcome,
    Reason, Step, WhyNot,
};
use scenalog_extractors::cache::Extractor;
use scenalog_facts::catalog::ColType;
use scenalog_facts::relation::Value;
use scenalog_facts::scene::{Frame, TrackId};
use scenalog_facts::Scene;
use scenalog_rules::ast::{CmpOp, Literal};
use scenalog_rules::printer::print_literal;
use scenalog_rules::CheckedProgram;
use serde_json::{json, Value as Json};

use super::scenario::Scenario;

/// How many characters of a track's uuid the text shows.
pub const UUID_PREFIX: usize = 8;

/// Evaluates a program on a scene for explaining. For a proof (`whole` false): provenance on,
/// catalog relations asked with the constraints the program implies, as `mine` does. For a
/// why-not report (`whole` true): provenance off, and catalog relations asked whole, without
/// the constants, categories and bounds, so the report sees the values that failed a
/// comparison or a constant (the speed that was not `< 0.5`, the direction that was not
/// `"right"`). Derived relations are the same either way: the engine filters again. Either runs
/// within `limits`' tuple budget and time limit (callers pass `mine`'s, from
/// [`super::budget::pair_limits`]), so a runaway program is an error here too, never a hang.
pub fn evaluate_for_explain(
    extractor: &Extractor<'_>,
    program: &CheckedProgram,
    whole: bool,
    limits: &Options,
) -> Result<Evaluation, EngineError> {
    let options = Options {
        provenance: !whole,
        ..limits.clone()
    };
    if whole {
        super::scenario::evaluate_on_whole(extractor, program, &options)
    } else {
        super::scenario::evaluate_on(extractor, program, &options)
    }
}

/// The frames at which `referred(track, frame)` is derived, ascending.
pub fn referred_frames(ev: &Evaluation, track: TrackId) -> Vec<Frame> {
    let mut frames: Vec<Frame> = ev
        .tuples("referred")
        .unwrap_or_default()
        .iter()
        .filter_map(|t| match t.as_slice() {
            [Value::Track(x), Value::Time(f)] if *x == track => Some(*f),
            _ => None,
        })
        .collect();
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// The frame whose time is nearest to `seconds` from the log's start (the earlier on a tie).
pub fn frame_nearest(scene: &Scene, seconds: f64) -> Option<Frame> {
    scene
        .timeline
        .frames()
        .iter()
        .copied()
        .filter_map(|f| scene.timeline.seconds(f).map(|s| (f, (s - seconds).abs())))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(f, _)| f)
}

/// The log's frame nearest `seconds` from its start, when `seconds` lies within the log's time
/// range (to half a 0.1 s step past either end); otherwise an error naming the range, so `--at
/// 999` on a 15 s log is refused rather than explaining the last frame.
pub fn frame_at(scene: &Scene, seconds: f64) -> Result<Frame, String> {
    let frames = scene.timeline.frames();
    let span = frames
        .first()
        .zip(frames.last())
        .and_then(|(a, b)| Some((scene.timeline.seconds(*a)?, scene.timeline.seconds(*b)?)));
    let Some((first, last)) = span else {
        return Err(format!("log {} has no frames", scene.log_id));
    };
    const HALF_STEP: f64 = 0.05;
    if seconds < first - HALF_STEP || seconds > last + HALF_STEP {
        return Err(format!(
            "--at {seconds}: outside log {}, which runs from {first:.1} s to {last:.1} s",
            scene.log_id
        ));
    }
    frame_nearest(scene, seconds).ok_or_else(|| format!("log {} has no frames", scene.log_id))
}

/// Renders values for a person, with the scene for names and times.
pub struct Renderer<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The scenario (its source gives rule text and lines).
    pub scenario: &'a Scenario,
}

/// The unit of a catalog relation's numeric column, if it has one.
fn unit(relation: &str, column: usize) -> &'static str {
    match (relation, column) {
        ("speed", 2) => " m/s",
        ("accel" | "lat_accel", 2) => " m/s²",
        ("yaw_rate", 2) => " deg/s",
        ("near", 3) | ("direction", 4 | 5) | ("near_intersection" | "at_crosswalk", 2) => " m",
        ("seconds", 1) => " s",
        ("frame_ns", 1) => " ns",
        _ => "",
    }
}

impl Renderer<'_> {
    fn types(&self, relation: &str) -> Vec<ColType> {
        self.scenario
            .program
            .predicates
            .get(relation)
            .map(|p| p.types.clone())
            .unwrap_or_default()
    }

    /// A track: uuid prefix and category.
    pub fn track(&self, t: TrackId) -> String {
        match self.scene.tracks.get(t.index()) {
            Some(tr) => {
                let prefix: String = tr.uuid.chars().take(UUID_PREFIX).collect();
                format!("{prefix} ({})", tr.category)
            }
            None => format!("track #{}", t.0),
        }
    }

    /// A frame: seconds from the log's start, and the frame index.
    pub fn frame(&self, f: Frame) -> String {
        match self.scene.timeline.seconds(f) {
            Some(s) => format!("{s:.1} s"),
            None => format!("frame {f}"),
        }
    }

    /// A value, with the unit of the column it came from (`relation`, `column`) when known.
    pub fn value(&self, v: &Value, at: Option<(&str, usize)>) -> String {
        let unit = at.map_or("", |(r, c)| unit(r, c));
        match v {
            Value::Track(t) => self.track(*t),
            Value::Time(f) => self.frame(*f),
            Value::Lane(l) => match self.scene.map.lane(*l) {
                Some(seg) => format!(
                    "lane {} ({}{})",
                    l.0,
                    seg.lane_type.as_str(),
                    if seg.is_intersection {
                        ", intersection"
                    } else {
                        ""
                    }
                ),
                None => format!("lane {}", l.0),
            },
            Value::Str(s) => format!("\"{s}\""),
            Value::Float(x) => format!("{x:.2}{unit}"),
            Value::Int(i) => format!("{i}{unit}"),
        }
    }

    /// A tuple as `relation(v, …)` with readable values.
    pub fn fact(&self, relation: &str, tuple: &[Value]) -> String {
        let args: Vec<String> = tuple
            .iter()
            .enumerate()
            .map(|(i, v)| self.value(v, Some((relation, i))))
            .collect();
        format!("{relation}({})", args.join(", "))
    }

    /// A pattern (`_` for unknown columns).
    pub fn pattern(&self, relation: &str, pattern: &[Option<Value>]) -> String {
        let args: Vec<String> = pattern
            .iter()
            .enumerate()
            .map(|(i, v)| match v {
                Some(v) => self.value(v, Some((relation, i))),
                None => "_".to_string(),
            })
            .collect();
        format!("{relation}({})", args.join(", "))
    }

    /// A value as JSON, as `scenalog facts --json` writes it.
    pub fn value_json(&self, v: &Value) -> Json {
        match v {
            Value::Track(t) => self
                .scene
                .tracks
                .get(t.index())
                .map_or(Json::Null, |tr| tr.uuid.clone().into()),
            Value::Time(f) => (*f).into(),
            Value::Lane(l) => l.0.into(),
            Value::Str(s) => s.as_ref().into(),
            Value::Float(x) => serde_json::Number::from_f64(*x).map_or(Json::Null, Json::Number),
            Value::Int(i) => (*i).into(),
        }
    }

    fn tuple_json(&self, t: &[Value]) -> Json {
        t.iter().map(|v| self.value_json(v)).collect()
    }

    fn pattern_json(&self, p: &[Option<Value>]) -> Json {
        p.iter()
            .map(|v| v.as_ref().map_or(Json::Null, |v| self.value_json(v)))
            .collect()
    }

    fn binding_json(&self, b: &[(String, Value)]) -> Json {
        let mut m = serde_json::Map::new();
        for (k, v) in b {
            m.insert(k.clone(), self.value_json(v));
        }
        Json::Object(m)
    }

    /// `V = 3f2a1b2c (REGULAR_VEHICLE), T = 4.2 s`.
    fn binding_text(&self, clause: Option<usize>, b: &[(String, Value)]) -> String {
        b.iter()
            .map(|(k, v)| format!("{k} = {}", self.value(v, self.var_origin(clause, k))))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The line (1-based) and source text of a clause.
    pub fn clause_source(&self, clause: usize) -> Option<(usize, String)> {
        let c = self.scenario.program.program.clauses.get(clause)?;
        let src = &self.scenario.source;
        if let Some(found) = scenalog_rules::prelude::clause_text(src.len(), c.span) {
            return Some(found);
        }
        let text = src.get(c.span.start..c.span.end)?.trim().to_string();
        let line = src.get(..c.span.start)?.matches('\n').count() + 1;
        Some((line, text))
    }

    fn clause_json(&self, clause: usize) -> Json {
        match self.clause_source(clause) {
            Some((line, text)) => json!({ "index": clause, "line": line, "text": text }),
            None => json!({ "index": clause, "line": Json::Null, "text": Json::Null }),
        }
    }

    fn file(&self) -> String {
        self.scenario.path.display().to_string()
    }

    /// The file a clause's text is in: the program's, or the prelude's for a clause the checker
    /// added from it.
    fn clause_file(&self, clause: usize) -> String {
        let from_prelude = self
            .scenario
            .program
            .program
            .clauses
            .get(clause)
            .is_some_and(|c| c.span.start > self.scenario.source.len());
        if from_prelude {
            format!("the prelude, {}", scenalog_rules::prelude::PATH)
        } else {
            self.file()
        }
    }

    pub(crate) fn literal(&self, clause: Option<usize>, li: usize) -> Option<&Literal> {
        self.scenario
            .program
            .program
            .clauses
            .get(clause?)?
            .body
            .get(li)
    }

    /// The relation and column that bind a variable in a clause (its first positive atom).
    fn var_origin(&self, clause: Option<usize>, var: &str) -> Option<(&str, usize)> {
        let c = self.scenario.program.program.clauses.get(clause?)?;
        for l in &c.body {
            if let Literal::Pos(a) = l {
                if let Some(i) = a.args.iter().position(|e| e.as_var() == Some(var)) {
                    return Some((a.pred.as_str(), i));
                }
            }
        }
        None
    }

    /// A side of a comparison: `speed = 0.21 m/s` when it is a variable bound by the only float
    /// column of a catalog relation, `Dist = 2.10 m` for another variable, the value otherwise.
    fn side(&self, clause: Option<usize>, e: &scenalog_rules::ast::Expr, v: &Value) -> String {
        let Some(var) = e.as_var() else {
            return self.value(v, None);
        };
        let origin = self.var_origin(clause, var);
        let text = self.value(v, origin);
        if let Some((rel, col)) = origin {
            let types = self.types(rel);
            let floats = types.iter().filter(|t| **t == ColType::Float).count();
            let catalog = scenalog_facts::catalog::relation(rel).is_some();
            if catalog && floats == 1 && types.get(col) == Some(&ColType::Float) {
                return format!("{rel} = {text}");
            }
        }
        format!("{var} = {text}")
    }

    fn comparison_text(
        &self,
        clause: Option<usize>,
        li: usize,
        lhs: Option<&Value>,
        op: CmpOp,
        rhs: Option<&Value>,
    ) -> String {
        let Some(Literal::Cmp(c)) = self.literal(clause, li) else {
            return format!("{lhs:?} {} {rhs:?}", op.as_str());
        };
        let l = lhs.map_or("(no value)".to_string(), |v| self.side(clause, &c.lhs, v));
        let r = rhs.map_or("(no value)".to_string(), |v| match c.rhs.as_var() {
            Some(_) => self.side(clause, &c.rhs, v),
            None => scenalog_rules::printer::print_expr(&c.rhs),
        });
        format!("{l} {} {r}", op.as_str())
    }

    pub(crate) fn body_fact_text(&self, clause: Option<usize>, f: &BodyFact) -> String {
        match f {
            BodyFact::Atom {
                relation, tuple, ..
            } => self.fact(relation, tuple),
            BodyFact::Absent {
                relation, pattern, ..
            } => format!("no {}", self.pattern(relation, pattern)),
            BodyFact::Comparison {
                literal,
                lhs,
                op,
                rhs,
                binds,
            } => match binds {
                Some(v) => format!("{v} = {}", self.value(lhs, None)),
                None => self.comparison_text(clause, *literal, Some(lhs), *op, Some(rhs)),
            },
            BodyFact::Aggregate {
                func,
                result,
                group_size,
                ..
            } => format!(
                "{} = {} (over {group_size} binding{})",
                func.as_str(),
                self.value(result, None),
                if *group_size == 1 { "" } else { "s" }
            ),
        }
    }

    /// A derivation as indented text (`header`: start with the derived fact's own line).
    pub fn derivation_text(&self, d: &Derivation, indent: usize, header: bool, out: &mut String) {
        let pad = " ".repeat(indent);
        let Some(ci) = d.clause else {
            out.push_str(&format!(
                "{pad}{} (from the log)\n",
                self.fact(&d.relation, &d.tuple)
            ));
            return;
        };
        if header {
            out.push_str(&format!("{pad}{}\n", self.fact(&d.relation, &d.tuple)));
        }
        if let Some((line, text)) = self.clause_source(ci) {
            out.push_str(&format!(
                "{pad}  by the rule at {}:{line}:\n",
                self.clause_file(ci)
            ));
            for l in text.lines() {
                out.push_str(&format!("{pad}    | {}\n", l.trim_end()));
            }
        }
        if !d.binding.is_empty() {
            out.push_str(&format!(
                "{pad}  with {}\n",
                self.binding_text(Some(ci), &d.binding)
            ));
        }
        for f in &d.body {
            let src = self
                .literal(Some(ci), f.literal())
                .map(print_literal)
                .unwrap_or_default();
            out.push_str(&format!(
                "{pad}  ✓ {src:<28}  {}\n",
                self.body_fact_text(Some(ci), f)
            ));
            if let BodyFact::Atom {
                derivation: Some(child),
                ..
            } = f
            {
                self.derivation_text(child, indent + 4, false, out);
            }
        }
    }

    /// A derivation as JSON (see the module documentation).
    pub fn derivation_json(&self, d: &Derivation) -> Json {
        let body: Vec<Json> = d
            .body
            .iter()
            .map(|f| {
                let source = self
                    .literal(d.clause, f.literal())
                    .map(print_literal)
                    .unwrap_or_default();
                let mut o = json!({
                    "literal": f.literal(),
                    "source": source,
                    "text": self.body_fact_text(d.clause, f),
                });
                let extra = match f {
                    BodyFact::Atom {
                        relation,
                        tuple,
                        derivation,
                        ..
                    } => json!({
                        "kind": "atom",
                        "relation": relation,
                        "tuple": self.tuple_json(tuple),
                        "derivation": derivation.as_ref().map_or(Json::Null, |c| self.derivation_json(c)),
                    }),
                    BodyFact::Absent {
                        relation, pattern, ..
                    } => json!({
                        "kind": "absent",
                        "relation": relation,
                        "pattern": self.pattern_json(pattern),
                    }),
                    BodyFact::Comparison {
                        lhs, op, rhs, binds, ..
                    } => json!({
                        "kind": "comparison",
                        "lhs": self.value_json(lhs),
                        "op": op.as_str(),
                        "rhs": self.value_json(rhs),
                        "binds": binds,
                    }),
                    BodyFact::Aggregate {
                        func,
                        result,
                        group_size,
                        ..
                    } => json!({
                        "kind": "aggregate",
                        "func": func.as_str(),
                        "result": self.value_json(result),
                        "group_size": group_size,
                    }),
                };
                merge(&mut o, extra);
                o
            })
            .collect();
        json!({
            "relation": d.relation,
            "tuple": self.tuple_json(&d.tuple),
            "text": self.fact(&d.relation, &d.tuple),
            "clause": d.clause.map_or(Json::Null, |c| self.clause_json(c)),
            "binding": self.binding_json(&d.binding),
            "body": body,
        })
    }

    pub(crate) fn step_text(&self, clause: usize, s: Step) -> String {
        match s {
            Step::Body(i) => self
                .literal(Some(clause), i)
                .map(print_literal)
                .unwrap_or_default(),
            Step::Head(i) => format!("head argument {}", i + 1),
        }
    }

    /// One line saying why a literal failed, with the values that failed it.
    pub fn reason_text(&self, clause: usize, f: &Failure) -> Vec<String> {
        let c = Some(clause);
        let mut lines = Vec::new();
        match &f.reason {
            Reason::Missing {
                relation,
                relation_size,
                wanted,
                closest,
                ..
            } => {
                match wanted.first() {
                    Some(p) => lines.push(format!(
                        "no {} among {relation_size} {relation} tuples",
                        self.pattern(relation, p)
                    )),
                    None => lines.push(format!("{relation} holds no tuple")),
                }
                for m in closest {
                    let cols: Vec<String> = m
                        .differs
                        .iter()
                        .map(|&i| self.column_name(relation, i))
                        .collect();
                    lines.push(format!(
                        "closest: {}{}",
                        self.fact(relation, &m.tuple),
                        if cols.is_empty() {
                            String::new()
                        } else {
                            format!(" (differs in {})", cols.join(", "))
                        }
                    ));
                }
            }
            Reason::Comparison { op, values } => {
                let n = f.binding_count;
                let li = match f.step {
                    Step::Body(i) => i,
                    Step::Head(_) => usize::MAX,
                };
                for v in values {
                    lines.push(format!(
                        "{}  is false  (with {})",
                        self.comparison_text(c, li, v.lhs.as_ref(), *op, v.rhs.as_ref()),
                        self.binding_text(c, &v.binding)
                    ));
                }
                if n > values.len() {
                    lines.push(format!(
                        "({n} bindings reached it; the {} closest to holding are shown)",
                        values.len()
                    ));
                }
            }
            Reason::Present { relation, found } => {
                for (b, t) in found {
                    lines.push(format!(
                        "{} holds  (with {})",
                        self.fact(relation, t),
                        self.binding_text(c, b)
                    ));
                }
            }
            Reason::Aggregate { func, values } => {
                for v in values {
                    let r = v
                        .result
                        .as_ref()
                        .map_or("no value (empty group)".to_string(), |r| {
                            self.value(r, None)
                        });
                    let need = v
                        .required
                        .as_ref()
                        .map(|q| format!(", must be {}", self.value(q, None)))
                        .unwrap_or_default();
                    lines.push(format!(
                        "{} = {r} over {} binding(s){need}  (with {})",
                        func.as_str(),
                        v.group_size,
                        self.binding_text(c, &v.binding)
                    ));
                }
            }
            Reason::HeadValue {
                column,
                wanted,
                values,
            } => {
                for (b, v) in values {
                    lines.push(format!(
                        "head argument {} is {}, the tuple has {}  (with {})",
                        column + 1,
                        v.as_ref()
                            .map_or("(no value)".to_string(), |v| self.value(v, None)),
                        self.value(wanted, None),
                        self.binding_text(c, b)
                    ));
                }
            }
            Reason::Unevaluable(m) => lines.push(m.clone()),
        }
        lines
    }

    /// A column's name: the catalog's, the `.decl`'s, or the variable the first rule for the
    /// relation has there.
    fn column_name(&self, relation: &str, i: usize) -> String {
        let program = &self.scenario.program.program;
        scenalog_facts::catalog::relation(relation)
            .and_then(|r| r.columns.get(i))
            .map(|c| c.name.to_string())
            .or_else(|| {
                let d = program.decls.iter().find(|d| d.name == relation)?;
                d.columns.get(i).map(|c| c.0.clone())
            })
            .or_else(|| {
                program
                    .clauses
                    .iter()
                    .filter(|c| c.head.pred == relation)
                    .find_map(|c| c.head.args.get(i)?.as_var().map(str::to_string))
            })
            .unwrap_or_else(|| format!("column {}", i + 1))
    }

    fn attempt_text(&self, a: &ClauseAttempt, indent: usize, out: &mut String, depth: usize) {
        let pad = " ".repeat(indent);
        if let Some((line, text)) = self.clause_source(a.clause) {
            out.push_str(&format!(
                "{pad}the rule at {}:{line}:\n",
                self.clause_file(a.clause)
            ));
            for l in text.lines() {
                out.push_str(&format!("{pad}    | {}\n", l.trim_end()));
            }
        }
        match &a.outcome {
            Outcome::Derives { binding, bindings } => out.push_str(&format!(
                "{pad}  derives it ({bindings} binding(s); e.g. {})\n",
                self.binding_text(Some(a.clause), binding)
            )),
            Outcome::HeadMismatch {
                column,
                expected,
                found,
            } => out.push_str(&format!(
                "{pad}  its head cannot match: argument {} is {expected}, the tuple has {}\n",
                column + 1,
                self.value(found, None)
            )),
            Outcome::Fails(f) => {
                for s in &f.held {
                    out.push_str(&format!("{pad}  ✓ {}\n", self.step_text(a.clause, *s)));
                }
                let n = f.binding_count;
                out.push_str(&format!(
                    "{pad}  ✗ {}   fails for {} that reached it{}\n",
                    f.text,
                    if n == 1 {
                        "the only binding".to_string()
                    } else {
                        format!("all {n} bindings")
                    },
                    if f.truncated {
                        " (bindings were capped)"
                    } else {
                        ""
                    }
                ));
                for l in self.reason_text(a.clause, f) {
                    out.push_str(&format!("{pad}      {l}\n"));
                }
                if let Reason::Missing {
                    nested: Some(n), ..
                } = &f.reason
                {
                    out.push_str(&format!(
                        "{pad}      why no {}:\n",
                        self.pattern(&n.relation, &n.pattern)
                    ));
                    self.why_not_body(n, indent + 8, out, depth + 1);
                }
            }
        }
    }

    fn why_not_body(&self, w: &WhyNot, indent: usize, out: &mut String, depth: usize) {
        let pad = " ".repeat(indent);
        if w.input {
            out.push_str(&format!(
                "{pad}{} is a relation from the log ({} tuples); {}\n",
                w.relation,
                w.relation_size,
                if w.holds {
                    "it holds"
                } else {
                    "it does not hold"
                }
            ));
            for m in &w.closest_input {
                out.push_str(&format!(
                    "{pad}  closest: {}\n",
                    self.fact(&w.relation, &m.tuple)
                ));
            }
            return;
        }
        let closest = w.closest();
        if let Some(a) = closest {
            if w.attempts.len() > 1 {
                out.push_str(&format!(
                    "{pad}closest of {} rules for {}:\n",
                    w.attempts.len(),
                    w.relation
                ));
            }
            self.attempt_text(a, indent, out, depth);
        } else {
            out.push_str(&format!("{pad}no rule derives {}\n", w.relation));
        }
        for a in &w.attempts {
            if Some(a.clause) == closest.map(|c| c.clause) {
                continue;
            }
            let line = self
                .clause_source(a.clause)
                .map_or(String::new(), |(l, _)| format!(":{l}"));
            let what = match &a.outcome {
                Outcome::Derives { .. } => "derives it".to_string(),
                Outcome::HeadMismatch { .. } => "its head cannot match".to_string(),
                Outcome::Fails(f) => {
                    format!("fails at {} after {} literal(s)", f.text, f.held.len())
                }
            };
            out.push_str(&format!("{pad}the rule at {}{line}: {what}\n", self.file()));
        }
    }

    /// A why-not report as indented text.
    pub fn why_not_text(&self, w: &WhyNot, out: &mut String) {
        let subject = self.pattern(&w.relation, &w.pattern);
        if w.holds {
            out.push_str(&format!("{subject} IS derived.\n"));
        } else {
            out.push_str(&format!("{subject} is not derived.\n"));
        }
        self.why_not_body(w, 2, out, 0);
    }

    fn failure_json(&self, clause: usize, f: &Failure) -> Json {
        let reason_lines = self.reason_text(clause, f).join("\n");
        let reason = match &f.reason {
            Reason::Missing {
                relation,
                relation_size,
                wanted,
                closest,
                nested,
            } => json!({
                "kind": "missing",
                "relation": relation,
                "relation_size": relation_size,
                "wanted": wanted.iter().map(|p| self.pattern_json(p)).collect::<Vec<_>>(),
                "closest": closest.iter().map(|m| json!({
                    "tuple": self.tuple_json(&m.tuple),
                    "differs": m.differs,
                })).collect::<Vec<_>>(),
                "nested": nested.as_ref().map_or(Json::Null, |n| self.why_not_json(n)),
            }),
            Reason::Comparison { op, values } => json!({
                "kind": "comparison",
                "op": op.as_str(),
                "values": values.iter().map(|v| json!({
                    "binding": self.binding_json(&v.binding),
                    "lhs": v.lhs.as_ref().map_or(Json::Null, |x| self.value_json(x)),
                    "rhs": v.rhs.as_ref().map_or(Json::Null, |x| self.value_json(x)),
                })).collect::<Vec<_>>(),
            }),
            Reason::Present { relation, found } => json!({
                "kind": "present",
                "relation": relation,
                "found": found.iter().map(|(b, t)| json!({
                    "binding": self.binding_json(b),
                    "tuple": self.tuple_json(t),
                })).collect::<Vec<_>>(),
            }),
            Reason::Aggregate { func, values } => json!({
                "kind": "aggregate",
                "func": func.as_str(),
                "values": values.iter().map(|v| json!({
                    "binding": self.binding_json(&v.binding),
                    "result": v.result.as_ref().map_or(Json::Null, |x| self.value_json(x)),
                    "required": v.required.as_ref().map_or(Json::Null, |x| self.value_json(x)),
                    "group_size": v.group_size,
                })).collect::<Vec<_>>(),
            }),
            Reason::HeadValue {
                column,
                wanted,
                values,
            } => json!({
                "kind": "head_value",
                "column": column,
                "wanted": self.value_json(wanted),
                "values": values.iter().map(|(b, v)| json!({
                    "binding": self.binding_json(b),
                    "value": v.as_ref().map_or(Json::Null, |x| self.value_json(x)),
                })).collect::<Vec<_>>(),
            }),
            Reason::Unevaluable(_) => json!({ "kind": "unevaluable" }),
        };
        let mut reason = reason;
        merge(&mut reason, json!({ "text": reason_lines }));
        json!({
            "step": match f.step {
                Step::Body(i) => json!({ "body": i }),
                Step::Head(i) => json!({ "head": i }),
            },
            "literal": f.text,
            "held": f.held.iter().map(|s| self.step_text(clause, *s)).collect::<Vec<_>>(),
            "bindings": f.bindings.iter().map(|b| self.binding_json(b)).collect::<Vec<_>>(),
            "binding_count": f.binding_count,
            "truncated": f.truncated,
            "reason": reason,
        })
    }

    /// A why-not report as JSON (see the module documentation).
    pub fn why_not_json(&self, w: &WhyNot) -> Json {
        let attempts: Vec<Json> = w
            .attempts
            .iter()
            .map(|a| {
                let mut o = json!({ "clause": self.clause_json(a.clause) });
                let extra = match &a.outcome {
                    Outcome::Derives { binding, bindings } => json!({
                        "outcome": "derives",
                        "binding": self.binding_json(binding),
                        "bindings": bindings,
                    }),
                    Outcome::HeadMismatch {
                        column,
                        expected,
                        found,
                    } => json!({
                        "outcome": "head_mismatch",
                        "column": column,
                        "expected": expected,
                        "found": self.value_json(found),
                    }),
                    Outcome::Fails(f) => json!({
                        "outcome": "fails",
                        "failure": self.failure_json(a.clause, f),
                    }),
                };
                merge(&mut o, extra);
                o
            })
            .collect();
        json!({
            "relation": w.relation,
            "pattern": self.pattern_json(&w.pattern),
            "holds": w.holds,
            "input": w.input,
            "relation_size": w.relation_size,
            "closest_input": w.closest_input.iter().map(|m| json!({
                "tuple": self.tuple_json(&m.tuple),
                "differs": m.differs,
            })).collect::<Vec<_>>(),
            "closest_clause": w.closest().map_or(Json::Null, |a| a.clause.into()),
            "attempts": attempts,
        })
    }
}

fn merge(into: &mut Json, from: Json) {
    if let (Json::Object(a), Json::Object(b)) = (into, from) {
        for (k, v) in b {
            a.insert(k, v);
        }
    }
}

/// Everything `scenalog explain` reports for one track and frame.
pub struct Explanation {
    /// The track.
    pub track: TrackId,
    /// The frame explained.
    pub frame: Frame,
    /// Frames at which the track is referred.
    pub referred_frames: Vec<Frame>,
    /// The grounded proof of `referred(track, frame)`, when it is derived.
    pub proof: Option<Derivation>,
    /// The why-not report, when asked for or when the track is not referred at the frame.
    pub why_not: Option<WhyNot>,
}

impl Explanation {
    /// Whether `referred(track, frame)` is derived.
    pub fn referred(&self) -> bool {
        self.referred_frames.binary_search(&self.frame).is_ok()
    }
}

/// The text `scenalog explain` prints.
pub fn explanation_text(r: &Renderer<'_>, e: &Explanation) -> String {
    let mut out = String::new();
    let n = e.referred_frames.len();
    let span = match (e.referred_frames.first(), e.referred_frames.last()) {
        (Some(a), Some(b)) => format!(" (from {} to {})", r.frame(*a), r.frame(*b)),
        _ => String::new(),
    };
    let uuid = r
        .scene
        .tracks
        .get(e.track.index())
        .map_or(String::new(), |t| t.uuid.clone());
    out.push_str(&format!(
        "{}: \"{}\" on log {}\n",
        r.file(),
        r.scenario.description,
        r.scene.log_id
    ));
    out.push_str(&format!(
        "track {uuid} ({}) is referred in {n} frame{}{span}\n",
        r.scene
            .tracks
            .get(e.track.index())
            .map_or("?", |t| t.category.as_str()),
        if n == 1 { "" } else { "s" }
    ));
    out.push_str(&format!(
        "at {} (frame {}): {}\n\n",
        r.frame(e.frame),
        e.frame,
        if e.referred() {
            "referred"
        } else {
            "NOT referred"
        }
    ));
    if let Some(p) = &e.proof {
        out.push_str("Proof:\n");
        r.derivation_text(p, 2, true, &mut out);
    }
    if let Some(w) = &e.why_not {
        if e.proof.is_some() {
            out.push('\n');
        }
        out.push_str("Why not:\n");
        r.why_not_text(w, &mut out);
    }
    out
}

/// The JSON `scenalog explain --json` prints (keys in the module documentation).
pub fn explanation_json(r: &Renderer<'_>, e: &Explanation) -> Json {
    let track = r.scene.tracks.get(e.track.index());
    let secs = |f: &Frame| r.scene.timeline.seconds(*f);
    json!({
        "log_id": r.scene.log_id,
        "rules": r.file(),
        "description": r.scenario.description,
        "track": {
            "uuid": track.map(|t| t.uuid.clone()),
            "category": track.map(|t| t.category.clone()),
        },
        "frame": e.frame,
        "seconds": secs(&e.frame),
        "referred": e.referred(),
        "referred_frames": e.referred_frames.len(),
        "referred_seconds": match (e.referred_frames.first(), e.referred_frames.last()) {
            (Some(a), Some(b)) => json!([secs(a), secs(b)]),
            _ => Json::Null,
        },
        "proof": e.proof.as_ref().map_or(Json::Null, |p| r.derivation_json(p)),
        "why_not": e.why_not.as_ref().map_or(Json::Null, |w| r.why_not_json(w)),
    })
}
