//! The proof and the why-not report as JSON (the keys the module's documentation lists).

use super::*;

pub(crate) fn merge(into: &mut Json, from: Json) {
    if let (Json::Object(a), Json::Object(b)) = (into, from) {
        for (k, v) in b {
            a.insert(k, v);
        }
    }
}

impl Renderer<'_> {
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

    pub(crate) fn tuple_json(&self, t: &[Value]) -> Json {
        t.iter().map(|v| self.value_json(v)).collect()
    }

    pub(crate) fn pattern_json(&self, p: &[Option<Value>]) -> Json {
        p.iter()
            .map(|v| v.as_ref().map_or(Json::Null, |v| self.value_json(v)))
            .collect()
    }

    pub(crate) fn binding_json(&self, b: &[(String, Value)]) -> Json {
        let mut m = serde_json::Map::new();
        for (k, v) in b {
            m.insert(k.clone(), self.value_json(v));
        }
        Json::Object(m)
    }

    pub(crate) fn clause_json(&self, clause: usize) -> Json {
        match self.clause_source(clause) {
            Some((line, text)) => json!({ "index": clause, "line": line, "text": text }),
            None => json!({ "index": clause, "line": Json::Null, "text": Json::Null }),
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

    pub(crate) fn failure_json(&self, clause: usize, f: &Failure) -> Json {
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
