//! Type inference by unification: every variable and every derived predicate's column gets a
//! type from the catalog, `.decl` lines (which win) and the uses. Reports E0103 (type mismatch),
//! E0104 (string outside a closed set of values) and E0402 (`referred`/`related` column types).

use std::collections::{BTreeMap, HashMap};

use scenalog_facts::catalog::{self, ColType};

use super::preds::{output_arity, PredTable};
use crate::ast::{AggFunc, Atom, Clause, Expr, ExprKind, Literal, Program, Span};
use crate::diagnostics::{self, error};
use crate::Diagnostic;

/// What is known of a class of unified things.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ty {
    Unknown,
    /// Some number (an integer literal): int, float or time.
    Num,
    Known(ColType),
}

impl Ty {
    fn describe(self) -> String {
        match self {
            Ty::Unknown => "value of unknown type".into(),
            Ty::Num => "number".into(),
            Ty::Known(ColType::Str) => "string".into(),
            Ty::Known(t) => t.as_str().into(),
        }
    }

    fn numeric_ok(self) -> bool {
        match self {
            Ty::Unknown | Ty::Num => true,
            Ty::Known(t) => t.is_numeric(),
        }
    }
}

/// Merges two types; `None` if they conflict.
fn merge(a: Ty, b: Ty) -> Option<Ty> {
    match (a, b) {
        (Ty::Unknown, x) | (x, Ty::Unknown) => Some(x),
        (Ty::Num, Ty::Num) => Some(Ty::Num),
        (Ty::Num, Ty::Known(t)) | (Ty::Known(t), Ty::Num) => t.is_numeric().then_some(Ty::Known(t)),
        (Ty::Known(x), Ty::Known(y)) => (x == y).then_some(a),
    }
}

fn article(s: &str) -> &'static str {
    if s.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}

fn a_ty(t: Ty) -> String {
    let s = t.describe();
    format!("{} {s}", article(&s))
}

/// Union-find over variables and predicate columns.
#[derive(Default)]
struct Classes {
    parent: Vec<usize>,
    ty: Vec<Ty>,
    /// Where the class got its type.
    origin: Vec<Option<(Span, String)>>,
    /// The closed set of values of a catalog string column the class was joined with.
    domain: Vec<Option<(&'static [&'static str], String)>>,
}

impl Classes {
    fn add(&mut self) -> usize {
        self.parent.push(self.parent.len());
        self.ty.push(Ty::Unknown);
        self.origin.push(None);
        self.domain.push(None);
        self.parent.len() - 1
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            let p = self.parent[x];
            self.parent[x] = self.parent[p];
            x = p;
        }
        x
    }

    /// Gives class `x` type `t`; on conflict returns the class's type and origin.
    fn constrain(
        &mut self,
        x: usize,
        t: Ty,
        origin: impl FnOnce() -> (Span, String),
    ) -> Result<(), (Ty, Option<(Span, String)>)> {
        let r = self.find(x);
        match merge(self.ty[r], t) {
            Some(m) => {
                if m != self.ty[r] {
                    if self.origin[r].is_none() || matches!(self.ty[r], Ty::Unknown | Ty::Num) {
                        self.origin[r] = Some(origin());
                    }
                    self.ty[r] = m;
                }
                Ok(())
            }
            None => Err((self.ty[r], self.origin[r].clone())),
        }
    }

    fn union(&mut self, a: usize, b: usize) -> Result<(), (Ty, Option<(Span, String)>)> {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra == rb {
            return Ok(());
        }
        match merge(self.ty[ra], self.ty[rb]) {
            Some(m) => {
                let origin = if self.ty[ra] == m && self.origin[ra].is_some() {
                    self.origin[ra].clone()
                } else {
                    self.origin[rb].clone().or_else(|| self.origin[ra].clone())
                };
                let domain = self.domain[ra].clone().or_else(|| self.domain[rb].clone());
                self.parent[rb] = ra;
                self.ty[ra] = m;
                self.origin[ra] = origin;
                self.domain[ra] = domain;
                Ok(())
            }
            None => Err((self.ty[ra], self.origin[ra].clone())),
        }
    }
}

/// What an argument position expects.
#[derive(Clone)]
enum Expect {
    /// A catalog column: its type, closed values and name.
    Fixed(ColType, &'static [&'static str], &'static str),
    /// A derived predicate's column (a class).
    Node(usize),
}

/// Where an argument is, for messages built only when something is wrong.
struct ArgAt<'a> {
    atom: &'a Atom,
    index: usize,
    code: &'static str,
}

impl ArgAt<'_> {
    fn what(&self) -> String {
        format!("argument {} of `{}`", self.index + 1, self.atom.pred)
    }

    fn column_desc(&self, col: &str) -> String {
        format!("`{}`'s column {} ({col})", self.atom.pred, self.index + 1)
    }

    fn hint(&self, d: Diagnostic) -> Diagnostic {
        let sig = match catalog::relation(&self.atom.pred) {
            Some(r) => Some(r.signature()),
            None => output_arity(&self.atom.pred).map(|(_, s)| s.to_string()),
        };
        match sig {
            Some(s) => d.with_hint(format!("the signature is {s}")),
            None => d,
        }
    }
}

struct Infer<'a> {
    cls: Classes,
    /// Column classes of derived predicates, by name.
    cols: HashMap<String, Vec<usize>>,
    table: &'a PredTable,
    /// Whether to report errors (the last round) or only learn types.
    report: bool,
    diags: Vec<Diagnostic>,
}

/// Infers the column types of every derived predicate, reporting E0103/E0104/E0402.
pub fn infer(
    program: &Program,
    table: &PredTable,
    diags: &mut Vec<Diagnostic>,
) -> BTreeMap<String, Vec<ColType>> {
    let mut inf = Infer {
        cls: Classes::default(),
        cols: HashMap::new(),
        table,
        report: true,
        diags: Vec::new(),
    };
    // Declared and required column types first: they win.
    for d in &program.decls {
        if table
            .preds
            .get(&d.name)
            .is_some_and(|e| e.origin == Some(d.span))
        {
            for (i, (name, ty)) in d.columns.iter().enumerate() {
                let n = inf.col(&d.name, i);
                let _ = inf.cls.constrain(n, Ty::Known(*ty), || {
                    (
                        d.span,
                        format!("`{}`'s column {name} is declared {ty} here", d.name),
                    )
                });
            }
        }
    }
    for (name, types) in [
        ("referred", &[ColType::Track, ColType::Time][..]),
        (
            "related",
            &[ColType::Track, ColType::Track, ColType::Time][..],
        ),
    ] {
        if table
            .preds
            .get(name)
            .is_some_and(|e| e.arity == types.len())
        {
            for (i, t) in types.iter().enumerate() {
                let n = inf.col(name, i);
                let sig = output_arity(name).map_or("", |(_, s)| s);
                let span = program
                    .clauses
                    .iter()
                    .find(|c| c.head.pred == name)
                    .map_or(Span::default(), |c| c.head.span);
                let _ = inf
                    .cls
                    .constrain(n, Ty::Known(*t), || (span, format!("the output is {sig}")));
            }
        }
    }
    // Per clause variable classes.
    let mut scopes: Vec<HashMap<String, usize>> =
        program.clauses.iter().map(|_| HashMap::new()).collect();
    // Atoms: bodies first, then heads (so head errors name the output's shape).
    for (c, scope) in program.clauses.iter().zip(scopes.iter_mut()) {
        for l in &c.body {
            inf.literal_atoms(l, scope);
        }
        if inf.table.fits(&c.head) {
            inf.atom(&c.head, scope, true);
        }
    }
    // Comparisons, bindings and aggregates: learn, then learn and report.
    for round in 0..3 {
        inf.report = round == 2;
        for (c, scope) in program.clauses.iter().zip(scopes.iter_mut()) {
            inf.clause_exprs(c, scope);
        }
    }
    // Strings in columns of the program's own predicates whose values are closed because the
    // column is joined with a closed catalog column somewhere (known only now).
    for c in &program.clauses {
        inf.closed_strings(&c.head);
        for l in &c.body {
            inf.closed_strings_in(l);
        }
    }
    diags.append(&mut inf.diags);
    let mut out = BTreeMap::new();
    for (name, e) in &table.preds {
        if e.kind != crate::PredKind::Derived {
            continue;
        }
        let types = (0..e.arity)
            .map(
                |i| match inf.cols.get(name).and_then(|v| v.get(i)).copied() {
                    Some(n) => {
                        let r = inf.cls.find(n);
                        match inf.cls.ty[r] {
                            Ty::Known(t) => t,
                            Ty::Num | Ty::Unknown => ColType::Int,
                        }
                    }
                    None => ColType::Int,
                },
            )
            .collect();
        out.insert(name.clone(), types);
    }
    out
}

impl Infer<'_> {
    fn col(&mut self, pred: &str, i: usize) -> usize {
        if let Some(&n) = self.cols.get(pred).and_then(|v| v.get(i)) {
            return n;
        }
        let mut v = self.cols.remove(pred).unwrap_or_default();
        while v.len() <= i {
            v.push(self.cls.add());
        }
        let n = v[i];
        self.cols.insert(pred.to_string(), v);
        n
    }

    fn var(&mut self, scope: &mut HashMap<String, usize>, name: &str) -> usize {
        if let Some(&n) = scope.get(name) {
            return n;
        }
        let n = self.cls.add();
        scope.insert(name.to_string(), n);
        n
    }

    fn literal_atoms(&mut self, l: &Literal, scope: &mut HashMap<String, usize>) {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) => {
                if self.table.fits(a) {
                    self.atom(a, scope, false);
                }
            }
            Literal::Cmp(_) => {}
            Literal::Agg(g) => {
                for l in &g.body {
                    self.literal_atoms(l, scope);
                }
            }
        }
    }

    fn push(&mut self, d: Diagnostic) {
        if self.report {
            self.diags.push(d);
        }
    }

    /// Unifies the arguments of `a` with its columns.
    fn atom(&mut self, a: &Atom, scope: &mut HashMap<String, usize>, is_head: bool) {
        let spec = catalog::relation(&a.pred);
        let code = if is_head && output_arity(&a.pred).is_some() {
            diagnostics::OUTPUT_SHAPE
        } else {
            diagnostics::TYPE_MISMATCH
        };
        for (i, arg) in a.args.iter().enumerate() {
            let expect = match spec {
                Some(r) => {
                    let c = r.columns[i];
                    Expect::Fixed(c.ty, c.values, c.name)
                }
                None => Expect::Node(self.col(&a.pred, i)),
            };
            let at = ArgAt {
                atom: a,
                index: i,
                code,
            };
            self.arg(arg, &expect, scope, &at);
        }
    }

    fn arg(&mut self, arg: &Expr, expect: &Expect, scope: &mut HashMap<String, usize>, at: &ArgAt) {
        let code = at.code;
        match (&arg.kind, expect) {
            (ExprKind::Wildcard, _) => {}
            (ExprKind::Var(v), Expect::Fixed(t, values, col)) => {
                let n = self.var(scope, v);
                let origin = || {
                    (
                        arg.span,
                        format!(
                            "`{v}` is {} here, {}",
                            a_ty(Ty::Known(*t)),
                            at.column_desc(col)
                        ),
                    )
                };
                match self.cls.constrain(n, Ty::Known(*t), origin) {
                    Ok(()) => {
                        if !values.is_empty() {
                            let r = self.cls.find(n);
                            if self.cls.domain[r].is_none() {
                                self.cls.domain[r] = Some((values, at.column_desc(col)));
                            }
                        }
                    }
                    Err((have, origin)) => {
                        let mut d = error(
                            code,
                            arg.span,
                            format!(
                                "type mismatch: {} is {}, but `{v}` is {}",
                                at.what(),
                                a_ty(Ty::Known(*t)),
                                a_ty(have)
                            ),
                        );
                        if let Some((s, l)) = origin {
                            d = d.with_related(s, l);
                        }
                        self.push(at.hint(d));
                    }
                }
            }
            (ExprKind::Var(v), Expect::Node(col)) => {
                let n = self.var(scope, v);
                if let Err((have, origin)) = self.cls.union(*col, n) {
                    let r = self.cls.find(n);
                    let vt = self.cls.ty[r];
                    let vo = self.cls.origin[r].clone();
                    let mut d = error(
                        code,
                        arg.span,
                        format!(
                            "type mismatch: {} is {}, but `{v}` is {}",
                            at.what(),
                            a_ty(have),
                            a_ty(vt)
                        ),
                    );
                    if let Some((s, l)) = origin {
                        d = d.with_related(s, l);
                    }
                    if let Some((s, l)) = vo {
                        d = d.with_related(s, l);
                    }
                    self.push(at.hint(d));
                }
            }
            (ExprKind::Str(s), Expect::Fixed(t, values, col)) => {
                if *t != ColType::Str {
                    let d = error(
                        code,
                        arg.span,
                        format!(
                            "type mismatch: {} is {}, found the string {s:?}",
                            at.what(),
                            a_ty(Ty::Known(*t))
                        ),
                    );
                    self.push(at.hint(d));
                } else if !values.is_empty() && !values.contains(&s.as_str()) {
                    self.push(bad_value(arg.span, s, values, &at.column_desc(col)));
                }
            }
            (_, Expect::Fixed(t, _, _)) => {
                let have = self.expr_ty(arg, scope);
                if merge(have, Ty::Known(*t)).is_none() {
                    let d = error(
                        code,
                        arg.span,
                        format!(
                            "type mismatch: {} is {}, found {}",
                            at.what(),
                            a_ty(Ty::Known(*t)),
                            a_ty(have)
                        ),
                    );
                    self.push(at.hint(d));
                }
            }
            (_, Expect::Node(col)) => {
                let have = self.expr_ty(arg, scope);
                let origin = || (arg.span, format!("{} is {} here", at.what(), a_ty(have)));
                if let Err((want, o)) = self.cls.constrain(*col, have, origin) {
                    let mut d = error(
                        code,
                        arg.span,
                        format!(
                            "type mismatch: {} is {}, found {}",
                            at.what(),
                            a_ty(want),
                            a_ty(have)
                        ),
                    );
                    if let Some((s, l)) = o {
                        d = d.with_related(s, l);
                    }
                    self.push(at.hint(d));
                }
            }
        }
    }

    /// The type of an expression, reporting arithmetic on non-numbers.
    fn expr_ty(&mut self, e: &Expr, scope: &mut HashMap<String, usize>) -> Ty {
        match &e.kind {
            ExprKind::Var(v) => {
                let n = self.var(scope, v);
                let r = self.cls.find(n);
                self.cls.ty[r]
            }
            ExprKind::Wildcard => Ty::Unknown,
            ExprKind::Str(_) => Ty::Known(ColType::Str),
            ExprKind::Int(_) => Ty::Num,
            ExprKind::Float(_) => Ty::Known(ColType::Float),
            ExprKind::Quantity(_) => Ty::Num,
            ExprKind::Neg(x) => self.numeric(x, scope, "`-`"),
            ExprKind::Binary(op, a, b) => {
                let what = format!("`{}`", op.as_str());
                let ta = self.numeric(a, scope, &what);
                let tb = self.numeric(b, scope, &what);
                combine(ta, tb)
            }
            ExprKind::Call(f, args) => {
                let what = format!("`{}`", f.as_str());
                let mut t = Ty::Num;
                let mut unknown = false;
                for a in args {
                    let ta = self.numeric(a, scope, &what);
                    unknown |= ta == Ty::Unknown;
                    t = combine(t, ta);
                }
                if unknown && t == Ty::Num {
                    Ty::Unknown
                } else {
                    t
                }
            }
        }
    }

    /// The type of an operand of arithmetic, which must be a number.
    fn numeric(&mut self, e: &Expr, scope: &mut HashMap<String, usize>, op: &str) -> Ty {
        let t = self.expr_ty(e, scope);
        if t.numeric_ok() {
            t
        } else {
            self.push(
                error(
                    diagnostics::TYPE_MISMATCH,
                    e.span,
                    format!("type mismatch: {op} needs numbers, found {}", a_ty(t)),
                )
                .with_hint("arithmetic works on int, float and time values"),
            );
            Ty::Unknown
        }
    }

    /// The type of `min`'s or `max`'s target, which must be a number or a string (strings
    /// are ordered by text).
    fn ordered(&mut self, e: &Expr, scope: &mut HashMap<String, usize>, func: AggFunc) -> Ty {
        let t = self.expr_ty(e, scope);
        if t.numeric_ok() || t == Ty::Known(ColType::Str) {
            return t;
        }
        self.push(
            error(
                diagnostics::TYPE_MISMATCH,
                e.span,
                format!(
                    "type mismatch: `{}` needs numbers or strings, found {}",
                    func.as_str(),
                    a_ty(t)
                ),
            )
            .with_hint("`min` and `max` order numbers by value and strings by text"),
        );
        Ty::Unknown
    }

    fn clause_exprs(&mut self, c: &Clause, scope: &mut HashMap<String, usize>) {
        for l in &c.body {
            self.literal_exprs(l, scope);
        }
    }

    fn literal_exprs(&mut self, l: &Literal, scope: &mut HashMap<String, usize>) {
        match l {
            Literal::Pos(_) | Literal::Neg(..) => {}
            Literal::Cmp(cmp) => {
                let tl = self.expr_ty(&cmp.lhs, scope);
                let tr = self.expr_ty(&cmp.rhs, scope);
                self.domain_check(&cmp.lhs, &cmp.rhs, scope);
                self.domain_check(&cmp.rhs, &cmp.lhs, scope);
                let time = Ty::Known(ColType::Time);
                let float = |t: Ty, e: &Expr| t == Ty::Known(ColType::Float) || has_float(e);
                if (tl == time || tr == time) && (float(tl, &cmp.lhs) || float(tr, &cmp.rhs)) {
                    // `T2 = T + 0.5` binds a time from arithmetic with a float; it compares
                    // nothing, so it is worded as what it does.
                    let binding = cmp.op == crate::ast::CmpOp::Eq
                        && (cmp.lhs.as_var().is_some() != cmp.rhs.as_var().is_some());
                    let (message, hint) = if binding {
                        (
                            "a time computed with a bare float: a time is a moment of the log, \
                             stored as tenths of a second",
                            "write the duration with its unit: `T2 = T + 0.5 s`",
                        )
                    } else {
                        (
                            "a time compared with a bare float: a time is a moment of the log, \
                             stored as tenths of a second",
                            "write durations with their unit (`T2 - T1 >= 2 s`); to compare \
                             seconds from the log's start, bind them with `seconds(T, S)`",
                        )
                    };
                    self.push(
                        diagnostics::warning(diagnostics::TIME_VS_FLOAT, cmp.span, message)
                            .with_hint(hint),
                    );
                }
                if cmp.op == crate::ast::CmpOp::Eq {
                    if let (Some(a), Some(b)) = (cmp.lhs.as_var(), cmp.rhs.as_var()) {
                        let (na, nb) = (self.var(scope, a), self.var(scope, b));
                        if self.cls.union(na, nb).is_err() {
                            self.push(compare_error(cmp.span, tl, tr));
                        }
                        return;
                    }
                    for (side, other) in [(&cmp.lhs, tr), (&cmp.rhs, tl)] {
                        if let Some(v) = side.as_var() {
                            let n = self.var(scope, v);
                            let span = cmp.span;
                            let _ = self.cls.constrain(n, other, || {
                                (span, format!("`{v}` is {} here", a_ty(other)))
                            });
                        }
                    }
                }
                let ok = merge(tl, tr).is_some() || (tl.numeric_ok() && tr.numeric_ok());
                if !ok {
                    self.push(compare_error(cmp.span, tl, tr));
                }
            }
            Literal::Agg(g) => {
                for l in &g.body {
                    self.literal_exprs(l, scope);
                }
                let result = match (g.func, &g.target) {
                    (AggFunc::Count, _) => Ty::Known(ColType::Int),
                    (AggFunc::Min | AggFunc::Max, Some(t)) => self.ordered(t, scope, g.func),
                    (_, Some(t)) => self.numeric(t, scope, &format!("`{}`", g.func.as_str())),
                    (_, None) => Ty::Unknown,
                };
                match &g.result.kind {
                    ExprKind::Var(v) => {
                        let n = self.var(scope, v);
                        let span = g.result.span;
                        let func = g.func.as_str();
                        if let Err((have, o)) = self.cls.constrain(n, result, || {
                            (
                                span,
                                format!("`{v}` is {} here, the result of `{func}`", a_ty(result)),
                            )
                        }) {
                            let mut d = error(
                                diagnostics::TYPE_MISMATCH,
                                g.result.span,
                                format!(
                                    "type mismatch: `{func}` gives {}, but `{v}` is {}",
                                    a_ty(result),
                                    a_ty(have)
                                ),
                            );
                            if let Some((s, l)) = o {
                                d = d.with_related(s, l);
                            }
                            self.push(d);
                        }
                    }
                    _ => {
                        let have = self.expr_ty(&g.result, scope);
                        if merge(have, result).is_none()
                            && !(have.numeric_ok() && result.numeric_ok())
                        {
                            self.push(compare_error(g.span, have, result));
                        }
                    }
                }
            }
        }
    }

    fn closed_strings_in(&mut self, l: &Literal) {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) => self.closed_strings(a),
            Literal::Cmp(_) => {}
            Literal::Agg(g) => g.body.iter().for_each(|l| self.closed_strings_in(l)),
        }
    }

    /// E0104 for a string constant in a column of a program predicate whose values are closed.
    fn closed_strings(&mut self, a: &Atom) {
        if catalog::relation(&a.pred).is_some() || !self.table.fits(a) {
            return;
        }
        for (i, arg) in a.args.iter().enumerate() {
            let ExprKind::Str(text) = &arg.kind else {
                continue;
            };
            let Some(n) = self.cols.get(&a.pred).and_then(|v| v.get(i)).copied() else {
                continue;
            };
            let r = self.cls.find(n);
            if let Some((values, desc)) = self.cls.domain[r].clone() {
                if !values.contains(&text.as_str()) {
                    let desc = format!("`{}`'s column {}, joined with {desc}", a.pred, i + 1);
                    self.push(bad_value(arg.span, text, values, &desc));
                }
            }
        }
    }

    /// E0104 when `s` is a string constant and `v` a variable joined with a closed-domain column.
    fn domain_check(&mut self, v: &Expr, s: &Expr, scope: &mut HashMap<String, usize>) {
        let (Some(name), ExprKind::Str(text)) = (v.as_var(), &s.kind) else {
            return;
        };
        let n = self.var(scope, name);
        let r = self.cls.find(n);
        if let Some((values, desc)) = self.cls.domain[r].clone() {
            if !values.contains(&text.as_str()) {
                self.push(bad_value(s.span, text, values, &desc));
            }
        }
    }
}

fn combine(a: Ty, b: Ty) -> Ty {
    use ColType::*;
    let rank = |t: Ty| match t {
        Ty::Known(Time) => 4,
        Ty::Known(Float) => 3,
        Ty::Known(Int) => 2,
        Ty::Num => 1,
        _ => 0,
    };
    if a == Ty::Unknown || b == Ty::Unknown {
        let other = if a == Ty::Unknown { b } else { a };
        return if rank(other) >= 2 { other } else { Ty::Unknown };
    }
    if rank(a) >= rank(b) {
        a
    } else {
        b
    }
}

fn compare_error(span: Span, a: Ty, b: Ty) -> Diagnostic {
    error(
        diagnostics::TYPE_MISMATCH,
        span,
        format!("type mismatch: cannot compare {} with {}", a_ty(a), a_ty(b)),
    )
    .with_hint("both sides of a comparison must be numbers (int, float, time), or both strings, tracks or lanes")
}

/// Whether a float literal occurs in `e`.
fn has_float(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Float(_) => true,
        ExprKind::Neg(a) => has_float(a),
        ExprKind::Binary(_, a, b) => has_float(a) || has_float(b),
        ExprKind::Call(_, args) => args.iter().any(has_float),
        _ => false,
    }
}

fn bad_value(span: Span, s: &str, values: &[&str], desc: &str) -> Diagnostic {
    let allowed: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
    let listed = format!("{desc} is one of {}", allowed.join(", "));
    let same_but_case = values.iter().find(|v| v.eq_ignore_ascii_case(s)).copied();
    let (suggest, hint) = match (same_but_case, catalog::value_alias(values, s)) {
        (Some(v), _) => (
            Some(v),
            format!("did you mean {v:?}? values are case-sensitive"),
        ),
        (None, Some(a)) => {
            let closest: Vec<String> = a.closest.iter().map(|v| format!("{v:?}")).collect();
            (
                a.closest.first().copied(),
                format!("{}; closest: {}. {listed}", a.note, closest.join(", ")),
            )
        }
        (None, None) => match diagnostics::closest(s, values.iter().copied(), 1).first() {
            Some(n) => (Some(*n), format!("did you mean {n:?}? {listed}")),
            None => (None, listed),
        },
    };
    let d = error(
        diagnostics::BAD_VALUE,
        span,
        format!("{s:?} is not a value of {desc}"),
    )
    .with_hint(hint);
    match suggest {
        Some(v) => d.with_edit(span, format!("{v:?}")),
        None => d,
    }
}
