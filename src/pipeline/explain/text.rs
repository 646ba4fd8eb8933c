//! The proof and the why-not report as text, for `scenalog explain`.

use super::values::TimeReading;
use super::*;

impl Renderer<'_> {
    /// `V = 3f2a1b2c (REGULAR_VEHICLE), T = 4.2 s`.
    pub(crate) fn binding_text(&self, clause: Option<usize>, b: &[(String, Value)]) -> String {
        b.iter()
            .map(|(k, v)| match self.is_time_var(clause, k) {
                // A time computed by arithmetic (`T0 = T - 1 s`) is held as a number.
                true => format!("{k} = {}", self.timed(Some(TimeReading::Instant), v)),
                false => format!("{k} = {}", self.value(v, self.var_origin(clause, k))),
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    pub(crate) fn comparison_text(
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
                Some(v) => {
                    let bound = match self.literal(clause, *literal) {
                        Some(Literal::Cmp(c)) => self.time_reading(clause, &c.rhs),
                        _ => None,
                    };
                    format!("{v} = {}", self.timed(bound, lhs))
                }
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

    pub(crate) fn step_text(&self, clause: usize, s: Step) -> String {
        match s {
            Step::Body(i) => self
                .literal(Some(clause), i)
                .map(print_literal)
                .unwrap_or_default(),
            Step::Head(i) => format!("head argument {}", i + 1),
        }
    }

    /// The near misses of a missing tuple, one line each, except that misses differing from
    /// what was wanted only in one time column, alike in every other and at consecutive frames,
    /// are one line giving the span (`stopped(X, T) for T from 7.6 s to 8.0 s`): five lines a
    /// frame apart say no more than that.
    fn closest_lines(&self, relation: &str, closest: &[NearMiss]) -> Vec<String> {
        let differs = |m: &NearMiss| -> String {
            let cols: Vec<String> = m
                .differs
                .iter()
                .map(|&i| self.column_name(relation, i))
                .collect();
            if cols.is_empty() {
                String::new()
            } else {
                format!(" (differs in {})", cols.join(", "))
            }
        };
        // The time column a miss differs in alone, and its frame.
        let time_only =
            |m: &NearMiss| match (m.differs.as_slice(), m.tuple.get(*m.differs.first()?)) {
                ([i], Some(Value::Time(f))) => Some((*i, *f)),
                _ => None,
            };
        let mut lines = Vec::new();
        let mut done = vec![false; closest.len()];
        for (k, m) in closest.iter().enumerate() {
            if done[k] {
                continue;
            }
            done[k] = true;
            let Some((col, f)) = time_only(m) else {
                lines.push(format!(
                    "closest: {}{}",
                    self.fact(relation, &m.tuple),
                    differs(m)
                ));
                continue;
            };
            // Its fellows: the same tuple but for the frame.
            let alike = |o: &NearMiss| {
                time_only(o).is_some_and(|(c, _)| c == col)
                    && o.tuple
                        .iter()
                        .zip(&m.tuple)
                        .enumerate()
                        .all(|(i, (a, b))| i == col || a == b)
            };
            let mut frames = vec![(f, k)];
            for (j, o) in closest.iter().enumerate().skip(k + 1) {
                if !done[j] && alike(o) {
                    if let Some((_, g)) = time_only(o) {
                        frames.push((g, j));
                    }
                }
            }
            frames.sort_unstable();
            // Split into runs of frames next to each other on the log's timeline.
            let mut runs: Vec<Vec<(Frame, usize)>> = Vec::new();
            for &(g, j) in &frames {
                match runs.last_mut() {
                    Some(r)
                        if r.last()
                            .is_some_and(|&(p, _)| self.scene.timeline.next(p) == Some(g)) =>
                    {
                        r.push((g, j))
                    }
                    _ => runs.push(vec![(g, j)]),
                }
            }
            for r in runs {
                let (first, j0) = r[0];
                if r.len() == 1 {
                    if j0 == k {
                        lines.push(format!(
                            "closest: {}{}",
                            self.fact(relation, &m.tuple),
                            differs(m)
                        ));
                    }
                    continue;
                }
                for &(_, j) in &r {
                    done[j] = true;
                }
                let last = r[r.len() - 1].0;
                let name = self.column_name(relation, col);
                let args: Vec<String> = m
                    .tuple
                    .iter()
                    .enumerate()
                    .map(|(i, v)| {
                        if i == col {
                            name.clone()
                        } else {
                            self.value(v, Some((relation, i)))
                        }
                    })
                    .collect();
                lines.push(format!(
                    "closest: {relation}({}) for {name} from {} to {} ({} frames; differs in {name})",
                    args.join(", "),
                    self.value(&Value::Time(first), Some((relation, col))),
                    self.value(&Value::Time(last), Some((relation, col))),
                    r.len()
                ));
            }
        }
        lines
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
                lines.extend(self.closest_lines(relation, closest));
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

    pub(crate) fn attempt_text(
        &self,
        a: &ClauseAttempt,
        indent: usize,
        out: &mut String,
        depth: usize,
    ) {
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

    pub(crate) fn why_not_body(&self, w: &WhyNot, indent: usize, out: &mut String, depth: usize) {
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
            out.push_str(&format!(
                "{pad}the rule at {}{line}: {what}\n",
                self.clause_file(a.clause)
            ));
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
}
