//! Values for a person: tracks as uuid prefix and category, frames as seconds from the log's
//! start, numbers with their unit, facts and patterns, and where a rule's text and variables
//! come from.

use scenalog_facts::units::{Dims, FRAME_S};

use super::*;

/// How a number computed from times reads ([`Renderer::time_reading`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TimeReading {
    /// A moment of the log (a frame).
    Instant,
    /// A length of time (frames counted).
    Duration,
}

/// The unit of a catalog relation's numeric column, if it has one.
pub(crate) fn unit(relation: &str, column: usize) -> &'static str {
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
    pub(crate) fn types(&self, relation: &str) -> Vec<ColType> {
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

    pub(crate) fn file(&self) -> String {
        self.scenario.path.display().to_string()
    }

    /// The file a clause's text is in: the program's, or the prelude's for a clause the checker
    /// added from it.
    pub(crate) fn clause_file(&self, clause: usize) -> String {
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
    pub(crate) fn var_origin(&self, clause: Option<usize>, var: &str) -> Option<(&str, usize)> {
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

    /// Whether variable `var` of a clause holds a time (its first positive atom binds it in a
    /// time column).
    pub(crate) fn is_time_var(&self, clause: Option<usize>, var: &str) -> bool {
        self.var_origin(clause, var)
            .is_some_and(|(rel, col)| self.types(rel).get(col) == Some(&ColType::Time))
    }

    /// How the value of expression `e` of a clause reads when it is computed from times: an
    /// instant for one time moved by a duration (`T - 1 s`), a duration for one time minus
    /// another (`T2 - T1`), `None` for anything else.
    pub(crate) fn time_reading(
        &self,
        clause: Option<usize>,
        e: &scenalog_rules::ast::Expr,
    ) -> Option<TimeReading> {
        use scenalog_rules::ast::{BinOp, ExprKind};
        match &e.kind {
            ExprKind::Var(v) if self.is_time_var(clause, v) => Some(TimeReading::Instant),
            ExprKind::Quantity(q) if q.measure().is_some_and(|m| m.dims == Dims::TIME) => {
                Some(TimeReading::Duration)
            }
            ExprKind::Binary(op @ (BinOp::Add | BinOp::Sub), a, b) => {
                match (self.time_reading(clause, a)?, self.time_reading(clause, b)?) {
                    (TimeReading::Instant, TimeReading::Instant) if *op == BinOp::Sub => {
                        Some(TimeReading::Duration)
                    }
                    (TimeReading::Instant, TimeReading::Duration)
                    | (TimeReading::Duration, TimeReading::Instant) => Some(TimeReading::Instant),
                    (TimeReading::Duration, TimeReading::Duration) => Some(TimeReading::Duration),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// A number computed from times, as it reads: an instant as a moment of the log (`3.9 s`),
    /// a duration in seconds (`3.0 s`); the plain value otherwise.
    pub(crate) fn timed(&self, reading: Option<TimeReading>, v: &Value) -> String {
        match (reading, v) {
            (Some(TimeReading::Instant), Value::Int(f)) => match u32::try_from(*f) {
                Ok(f) => self.frame(f),
                Err(_) => self.value(v, None),
            },
            (Some(TimeReading::Duration), Value::Int(n)) => format!("{:.1} s", *n as f64 * FRAME_S),
            _ => self.value(v, None),
        }
    }

    /// A side of a comparison: `speed = 0.21 m/s` when it is a variable bound by the only float
    /// column of a catalog relation, `Dist = 2.10 m` for another variable, the value otherwise.
    pub(crate) fn side(
        &self,
        clause: Option<usize>,
        e: &scenalog_rules::ast::Expr,
        v: &Value,
    ) -> String {
        let Some(var) = e.as_var() else {
            return match self.time_reading(clause, e) {
                Some(r) => format!(
                    "{} = {}",
                    scenalog_rules::printer::print_expr(e),
                    self.timed(Some(r), v)
                ),
                None => self.value(v, None),
            };
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

    /// A column's name: the catalog's, the `.decl`'s, or the variable the first rule for the
    /// relation has there.
    pub(crate) fn column_name(&self, relation: &str, i: usize) -> String {
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
}
