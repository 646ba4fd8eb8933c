//! Safety (every variable bound by a positive atom or a binding: E0201) and variables used
//! once (W0501).

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

use crate::ast::{Clause, CmpOp, Expr, ExprKind, Literal, Span};
use crate::diagnostics::{self, error, warning};
use crate::walk;
use crate::Diagnostic;

fn expr_vars(e: &Expr) -> Vec<(&str, Span)> {
    let mut out = Vec::new();
    walk::expr_vars_spanned(e, &mut out);
    out
}

/// The variables bound at a point of a clause: those of its own body (or an aggregate's braces)
/// and, for braces, those of the bodies around them.
struct Scope<'s> {
    outer: Option<&'s Scope<'s>>,
    own: HashSet<&'s str>,
}

impl Scope<'_> {
    fn contains(&self, v: &str) -> bool {
        self.own.contains(v) || self.outer.is_some_and(|o| o.contains(v))
    }
}

/// What positive atoms, aggregates' results and bindings of `body` bind, given `outer`'s
/// variables. A binding `X = E` binds `X` once every variable of `E` is bound, so the bindings
/// are resolved by a worklist: each waits on a count of its unbound variables and is taken when
/// the count reaches zero, in time linear in the body whatever order they are written in.
fn bind<'s>(body: &'s [Literal], outer: Option<&'s Scope<'s>>) -> Scope<'s> {
    let mut scope = Scope {
        outer,
        own: HashSet::new(),
    };
    for l in body {
        match l {
            Literal::Pos(a) => {
                for v in a.args.iter().filter_map(|e| e.as_var()) {
                    if !scope.contains(v) {
                        scope.own.insert(v);
                    }
                }
            }
            Literal::Agg(g) => {
                if let Some(v) = g.result.as_var() {
                    if !scope.contains(v) {
                        scope.own.insert(v);
                    }
                }
            }
            _ => {}
        }
    }
    // Each binding: the variable it binds and how many of its expression's are still unbound.
    let mut targets: Vec<(&str, usize)> = Vec::new();
    let mut waiting: HashMap<&str, Vec<usize>> = HashMap::new();
    let mut ready: Vec<usize> = Vec::new();
    for l in body {
        let Literal::Cmp(c) = l else { continue };
        if c.op != CmpOp::Eq {
            continue;
        }
        for (side, other) in [(&c.lhs, &c.rhs), (&c.rhs, &c.lhs)] {
            let Some(v) = side.as_var() else { continue };
            let mut unbound: Vec<&str> = expr_vars(other)
                .into_iter()
                .map(|(w, _)| w)
                .filter(|w| !scope.contains(w))
                .collect();
            unbound.sort_unstable();
            unbound.dedup();
            let id = targets.len();
            targets.push((v, unbound.len()));
            if unbound.is_empty() {
                ready.push(id);
            }
            for w in unbound {
                waiting.entry(w).or_default().push(id);
            }
        }
    }
    while let Some(id) = ready.pop() {
        let v = targets[id].0;
        if scope.contains(v) {
            continue;
        }
        scope.own.insert(v);
        for &next in waiting.get(v).map_or(&[][..], Vec::as_slice) {
            targets[next].1 -= 1;
            if targets[next].1 == 0 {
                ready.push(next);
            }
        }
    }
    scope
}

struct Safety {
    diags: Vec<Diagnostic>,
    reported: BTreeSet<String>,
}

impl Safety {
    fn unbound(&mut self, name: &str, span: Span, place: &dyn Fn() -> String, hint: &str) {
        let place = place();
        if self.reported.insert(name.to_string()) {
            self.diags.push(
                error(
                    diagnostics::UNSAFE_VARIABLE,
                    span,
                    format!(
                        "unsafe variable `{name}` in {place}: no positive atom or binding binds it"
                    ),
                )
                .with_hint(hint.replace("{V}", name)),
            );
        }
    }

    fn wildcard(&mut self, span: Span, place: &str) {
        self.diags.push(
            error(
                diagnostics::UNSAFE_VARIABLE,
                span,
                format!("`_` cannot appear in {place}: it stands for a value that is never bound"),
            )
            .with_hint("use a named variable bound by a positive atom of the body"),
        );
    }

    fn check_exprs<'a>(
        &mut self,
        exprs: impl IntoIterator<Item = &'a Expr>,
        bound: &Scope<'_>,
        place: &dyn Fn() -> String,
        hint: &str,
    ) {
        for e in exprs {
            for (v, s) in expr_vars(e) {
                if !bound.contains(v) {
                    self.unbound(v, s, place, hint);
                }
            }
        }
    }

    fn body(&mut self, body: &[Literal], bound: &Scope<'_>) {
        const HINT: &str = "bind `{V}` in a positive atom of the body (e.g. `speed(X, T, {V})`) or with `{V} = expression`";
        for l in body {
            match l {
                Literal::Pos(a) => {
                    let complex: Vec<&Expr> = a.args.iter().filter(|e| e.as_var().is_none()).collect();
                    self.check_exprs(complex, bound, &|| format!("an argument of `{}`", a.pred), HINT);
                }
                Literal::Neg(a, _) => self.check_exprs(
                    &a.args,
                    bound,
                    &|| format!("the negation of `{}`", a.pred),
                    "bind `{V}` in a positive atom before negating, or write `_` if any value will do",
                ),
                Literal::Cmp(c) => {
                    let mut w = Vec::new();
                    walk::wildcards(&c.lhs, &mut w);
                    walk::wildcards(&c.rhs, &mut w);
                    for s in w {
                        self.wildcard(s, "a comparison");
                    }
                    self.check_exprs([&c.lhs, &c.rhs], bound, &|| "a comparison".into(), HINT);
                }
                Literal::Agg(g) => {
                    let inner = bind(&g.body, Some(bound));
                    if matches!(g.result.kind, ExprKind::Wildcard) {
                        self.wildcard(g.result.span, "an aggregate's result");
                    }
                    if let Some(t) = &g.target {
                        self.check_exprs([t], &inner, &|| format!("the target of `{}`", g.func.as_str()), HINT);
                    }
                    self.body(&g.body, &inner);
                }
            }
        }
    }
}

/// Reports unsafe variables (E0201) and variables used once (W0501) in one clause.
pub fn check_clause(c: &Clause, diags: &mut Vec<Diagnostic>) {
    let bound = bind(&c.body, None);
    let mut s = Safety {
        diags: Vec::new(),
        reported: BTreeSet::new(),
    };
    for arg in &c.head.args {
        let mut w = Vec::new();
        walk::wildcards(arg, &mut w);
        for sp in w {
            s.wildcard(sp, "the head");
        }
    }
    s.check_exprs(
        &c.head.args,
        &bound,
        &|| "the head".into(),
        "every variable of the head must appear in a positive atom of the body (e.g. `present({V}, T)`) or a binding `{V} = expression`",
    );
    s.body(&c.body, &bound);
    // Singletons.
    let mut count: BTreeMap<&str, (usize, Span)> = BTreeMap::new();
    let mut all = Vec::new();
    for e in &c.head.args {
        walk::expr_vars_spanned(e, &mut all);
    }
    walk::literal_vars_spanned(&c.body, &mut all);
    for (v, sp) in all {
        let e = count.entry(v).or_insert((0, sp));
        e.0 += 1;
    }
    // A variable only inside a `count` body is what is counted: not a slip.
    let mut counted = Vec::new();
    count_vars(&c.body, false, &mut counted);
    let counted: HashSet<&str> = counted.into_iter().collect();
    let mut places: Option<Places> = None;
    for (v, (n, sp)) in count {
        if n == 1 && !v.starts_with('_') && !s.reported.contains(v) && !counted.contains(v) {
            let d = warning(
                diagnostics::SINGLETON,
                sp,
                format!("variable `{v}` is used only once"),
            );
            let places = places.get_or_insert_with(|| Places::of(c));
            s.diags.push(match places.other_object(v) {
                Some(o) => o.hint(d, v),
                None => d.with_hint(singleton_hint(v)),
            });
        }
    }
    diags.append(&mut s.diags);
}

/// Variables inside the bodies of `count` aggregates.
fn count_vars<'a>(body: &'a [Literal], in_count: bool, out: &mut Vec<&'a str>) {
    for l in body {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) if in_count => {
                a.args.iter().for_each(|e| walk::expr_vars(e, out));
            }
            Literal::Agg(g) => count_vars(
                &g.body,
                in_count || g.func == crate::ast::AggFunc::Count,
                out,
            ),
            _ => {}
        }
    }
}

/// A singleton that is an object a catalog relation relates to another: the relation, and the
/// category another object of the same atom is given, if any.
struct OtherObject<'a> {
    pred: &'a str,
    /// The atom's end, where a `category` for the singleton goes.
    end: usize,
    /// The category a sibling object of the atom has (`in_between(X, P1, P2, T)` with
    /// `category(P1, "PEDESTRIAN")`).
    sibling: Option<&'a str>,
}

impl OtherObject<'_> {
    fn hint(&self, d: Diagnostic, v: &str) -> Diagnostic {
        let pred = self.pred;
        match self.sibling {
            Some(cat) => d
                .with_hint(format!(
                    "`{v}` is an object `{pred}` relates: with `_` any object would do; the \
                     other one is a {cat:?}, so say what `{v}` is too: `category({v}, {cat:?})`"
                ))
                .with_edit(
                    Span::new(self.end, self.end),
                    format!(", category({v}, {cat:?})"),
                ),
            None => d.with_hint(format!(
                "`{v}` is an object `{pred}` relates: say what it is (e.g. `category({v}, \
                 \"VEHICLE\")`), or write `_` if any object will do"
            )),
        }
    }
}

/// Where each variable first occurs in a positive atom, and the category each variable is
/// given, built once a clause with singletons: each singleton's lookup is then a few steps,
/// not a scan of a body that may hold thousands of atoms.
struct Places<'a> {
    first: HashMap<&'a str, (&'a crate::ast::Atom, usize)>,
    category: HashMap<&'a str, &'a str>,
}

impl<'a> Places<'a> {
    fn of(c: &'a Clause) -> Places<'a> {
        let mut first = HashMap::new();
        let mut category = HashMap::new();
        for l in &c.body {
            let Literal::Pos(a) = l else { continue };
            for (i, e) in a.args.iter().enumerate() {
                if let Some(v) = e.as_var() {
                    first.entry(v).or_insert((a, i));
                }
            }
            if a.pred == "category" {
                if let (
                    Some(x),
                    Some(Expr {
                        kind: ExprKind::Str(k),
                        ..
                    }),
                ) = (a.args.first().and_then(|e| e.as_var()), a.args.get(1))
                {
                    category.entry(x).or_insert(k.as_str());
                }
            }
        }
        Places { first, category }
    }

    /// Where singleton `v` is a track column of a catalog atom other than its first.
    fn other_object(&self, v: &str) -> Option<OtherObject<'a>> {
        let &(a, at) = self.first.get(v)?;
        let rel = scenalog_facts::catalog::relation(&a.pred)?;
        let track = |i: usize| {
            rel.columns
                .get(i)
                .is_some_and(|col| col.ty == scenalog_facts::catalog::ColType::Track)
        };
        if at == 0 || !track(at) {
            return None;
        }
        let sibling = a
            .args
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != 0 && i != at && track(i))
            .find_map(|(_, e)| self.category.get(e.as_var()?).copied());
        Some(OtherObject {
            pred: &a.pred,
            end: a.span.end,
            sibling,
        })
    }
}

fn singleton_hint(v: &str) -> String {
    let mut hint = format!("if any value will do, write `_` (or `_{v}` to keep the name); otherwise check its spelling");
    if v.len() > 1 && v.chars().all(|c| c.is_ascii_uppercase() || c == '_') {
        hint.push_str(&format!("; if you meant the string, quote it: \"{v}\""));
    }
    hint
}
