//! Units: every number is read against what it is compared with, added to or stored in.
//!
//! A variable gets the unit of the catalog column that binds it (`speed`'s `V` is m/s, a time
//! column is an instant in frames of 0.1 s) or of the expression assigned to it; a derived
//! relation's column gets the unit its rules put there. A literal with a unit (`50 km/h`,
//! `3 s`) is then converted into the unit of its place ([`Quantity::read_as`]: 13.89 for a
//! speed, 30 for a duration of frames); a bare number is read in that unit and, unless it is 0
//! or a plain count, gets W0511 saying how it was read with a fix that writes the unit. Units of
//! different dimensions that meet — a speed compared with a distance, an instant plus an instant
//! — are E0105; a bare number added to an instant is E0106 (`T + 1` is a frame at 10 Hz and no
//! sample at all at 2 Hz), whose fix writes the same time in seconds.

use std::collections::HashMap;

use scenalog_facts::catalog;
use scenalog_facts::units::{parse_unit, readable, Dims, Measure, FRAME_S};

use crate::ast::{
    AggFunc, BinOp, Clause, Expr, ExprKind, Func, Literal, Number, Program, Quantity, Span,
};
use crate::diagnostics::{self, error, warning};
use crate::Diagnostic;

/// Rounds of inference of derived relations' column units (a chain of helpers this deep).
const ROUNDS: usize = 8;

/// What is known of the unit of an expression.
#[derive(Debug, Clone, Copy, PartialEq)]
enum U {
    /// Nothing: a string, a track, an unbound variable, a column with no unit.
    Unknown,
    /// A plain number: a literal with its value and place, or arithmetic of literals (`None`).
    Bare(Option<(f64, Span)>),
    /// Literals with units only: read in whatever unit of these dimensions the place has.
    Flex(Dims),
    /// A measure.
    Known(Measure),
    /// A measure times (or over, `inverse`) a bare literal: the literal may be a plain factor
    /// or a quantity whose unit was left out (`S * 1.0` for a distance covered in 1 s).
    Scaled(Measure, (f64, Span), bool),
}

impl U {
    /// The measure of a known unit, or of literals with units read in base units.
    fn measure(self) -> Option<Measure> {
        match self {
            U::Known(m) | U::Scaled(m, ..) => Some(m),
            U::Flex(d) => Some(Measure::base(d)),
            U::Unknown | U::Bare(_) => None,
        }
    }
}

/// Something wrong (or worth saying) where two units meet.
#[derive(Debug, Clone, PartialEq)]
enum Finding {
    /// Incompatible units, in words.
    Mismatch(String),
    /// A bare literal read in a unit.
    BareRead(f64, Span, Measure),
    /// A bare literal added to an instant.
    InstantPlusBare(f64, Span, Measure),
    /// A bare factor that makes a product measure something else than what it meets: the
    /// literal, the dimensions it would need, what the product is and what it meets.
    UnitlessFactor(f64, Span, Dims, Measure, Measure),
}

/// A scaled side meeting another: the finding when its factor must have had a unit, and the
/// sides with the scaled one read as its measure.
fn unscale(a: U, b: U) -> (U, U, Option<Finding>) {
    let other = |u: U| match u {
        U::Scaled(..) | U::Unknown | U::Bare(_) => None,
        u => u.measure(),
    };
    for (x, y) in [(a, b), (b, a)] {
        if let (U::Scaled(m, (v, span), inverse), Some(o)) = (x, other(y)) {
            if m.dims != o.dims {
                let need = if inverse {
                    Dims::NONE.over(o.dims.over(m.dims))
                } else {
                    o.dims.over(m.dims)
                };
                let f = Finding::UnitlessFactor(v, span, need, m, o);
                return (U::Known(o), U::Known(o), Some(f));
            }
        }
    }
    let plain = |u: U| match u {
        U::Scaled(m, ..) => U::Known(m),
        u => u,
    };
    (plain(a), plain(b), None)
}

/// Units of every variable of one clause.
type Env = HashMap<String, Measure>;

/// Units of derived relations' columns.
type Columns = HashMap<String, Vec<Option<Measure>>>;

/// Reads every number of `program` in its place's unit (setting each quantity's `read_as`) and
/// reports E0105, E0106 and W0511.
pub fn check_program(program: &mut Program, diags: &mut Vec<Diagnostic>) {
    let w0504: Vec<Span> = diags
        .iter()
        .filter(|d| d.code == diagnostics::TIME_VS_FLOAT)
        .map(|d| d.span)
        .collect();
    // A `.decl`'s units (`V: float<m/s>`) first: they win over what the rules put there.
    let mut cols: Columns = HashMap::new();
    for d in &program.decls {
        let measures = d.units.iter().map(|u| parse_unit(u.as_deref()?)).collect();
        cols.insert(d.name.clone(), measures);
    }
    for _ in 0..ROUNDS {
        let mut changed = false;
        for c in &program.clauses {
            let env = infer_env(c, &cols, &mut Vec::new());
            let heads = c
                .head
                .args
                .iter()
                .map(|a| measure(a, &env).measure())
                .collect::<Vec<_>>();
            let entry = cols
                .entry(c.head.pred.clone())
                .or_insert_with(|| vec![None; heads.len()]);
            for (slot, m) in entry.iter_mut().zip(heads) {
                if slot.is_none() && m.is_some() {
                    *slot = m;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    for c in &mut program.clauses {
        let mut found = Vec::new();
        let env = infer_env(c, &cols, &mut found);
        for (i, arg) in c.head.args.iter().enumerate() {
            let col = column(&c.head.pred, i, &cols);
            if let (Some(want), Some(have)) = (col, measure(arg, &env).measure()) {
                if want.dims != have.dims {
                    found.push((
                        arg.span,
                        Finding::Mismatch(format!(
                            "column {} of `{}` is {} in another rule, {} here",
                            i + 1,
                            c.head.pred,
                            want.describe(),
                            have.describe()
                        )),
                    ));
                }
            }
        }
        let mut at = Settle {
            env: &env,
            cols: &cols,
            found: &mut found,
        };
        for arg in &mut c.head.args {
            at.settle(arg, None);
        }
        for l in &mut c.body {
            at.literal(l);
        }
        for (span, f) in found {
            // A bare float next to a time is W0504's already.
            let said = matches!(f, Finding::BareRead(_, at, m) if m.dims == Dims::TIME
                && w0504.iter().any(|s| s.start <= at.start && at.end <= s.end));
            if !said {
                diags.push(report(span, f));
            }
        }
    }
}

/// The unit of column `i` of `pred`: the catalog's, or what the program's rules put there.
fn column(pred: &str, i: usize, cols: &Columns) -> Option<Measure> {
    match catalog::relation(pred) {
        Some(r) => r.columns.get(i).and_then(|c| c.unit.measure()),
        None => cols.get(pred).and_then(|v| v.get(i).copied().flatten()),
    }
}

/// Every comparison and aggregate of `body` (inside aggregates too).
fn bindings<'a>(body: &'a [Literal], out: &mut Vec<&'a Literal>) {
    for l in body {
        match l {
            Literal::Cmp(_) => out.push(l),
            Literal::Agg(g) => {
                out.push(l);
                bindings(&g.body, out);
            }
            Literal::Pos(_) | Literal::Neg(..) => {}
        }
    }
}

/// The units of a clause's variables: from the columns that bind them, then from what is
/// assigned to them. A variable bound by columns of different dimensions is a finding.
fn infer_env(c: &Clause, cols: &Columns, found: &mut Vec<(Span, Finding)>) -> Env {
    let mut env = Env::new();
    for (a, _) in crate::walk::body_atoms(&c.body) {
        for (i, arg) in a.args.iter().enumerate() {
            let (Some(v), Some(m)) = (arg.as_var(), column(&a.pred, i, cols)) else {
                continue;
            };
            match env.get(v) {
                None => {
                    env.insert(v.to_string(), m);
                }
                Some(had) if had.dims != m.dims => found.push((
                    arg.span,
                    Finding::Mismatch(format!(
                        "`{v}` is {} here (column {} of `{}`) and {} elsewhere in the rule",
                        m.describe(),
                        i + 1,
                        a.pred,
                        had.describe()
                    )),
                )),
                Some(_) => {}
            }
        }
    }
    let mut lits = Vec::new();
    bindings(&c.body, &mut lits);
    for _ in 0..3 {
        let before = env.len();
        for l in &lits {
            match l {
                Literal::Cmp(cmp) if cmp.op == crate::ast::CmpOp::Eq => {
                    for (side, other) in [(&cmp.lhs, &cmp.rhs), (&cmp.rhs, &cmp.lhs)] {
                        if let Some(v) = side.as_var() {
                            if !env.contains_key(v) {
                                if let Some(m) = measure(other, &env).measure() {
                                    env.insert(v.to_string(), m);
                                }
                            }
                        }
                    }
                }
                Literal::Agg(g) => {
                    let Some(v) = g.result.as_var() else { continue };
                    if env.contains_key(v) {
                        continue;
                    }
                    let m = match (&g.func, &g.target) {
                        (AggFunc::Count, _) => Some(Measure::NONE),
                        (_, Some(t)) => measure(t, &env).measure(),
                        (_, None) => None,
                    };
                    if let Some(m) = m {
                        env.insert(v.to_string(), m);
                    }
                }
                _ => {}
            }
        }
        if env.len() == before {
            break;
        }
    }
    env
}

/// The unit of an expression (no reporting).
fn measure(e: &Expr, env: &Env) -> U {
    match &e.kind {
        ExprKind::Var(v) => env.get(v.as_str()).map_or(U::Unknown, |m| U::Known(*m)),
        ExprKind::Wildcard | ExprKind::Str(_) => U::Unknown,
        ExprKind::Int(i) => U::Bare(Some((*i as f64, e.span))),
        ExprKind::Float(f) => U::Bare(Some((*f, e.span))),
        ExprKind::Quantity(q) => q.measure().map_or(U::Unknown, |m| U::Flex(m.dims)),
        ExprKind::Neg(x) => match measure(x, env) {
            U::Bare(Some((v, _))) => U::Bare(Some((-v, e.span))),
            u => u,
        },
        ExprKind::Binary(op, a, b) => {
            let (ua, ub) = (measure(a, env), measure(b, env));
            match op {
                BinOp::Add | BinOp::Sub => add(*op, ua, ub).0,
                BinOp::Mul | BinOp::Div => mul(*op, ua, ub),
                // A remainder is in its dividend's unit (`D mod 5 m`, both sides alike).
                BinOp::Mod => add(BinOp::Sub, ua, ub).0,
                // A power of a bare number is a bare number; of a quantity, a unit this check
                // does not follow.
                BinOp::Pow => match (ua, ub) {
                    (U::Bare(_), U::Bare(_)) => U::Bare(None),
                    _ => U::Unknown,
                },
            }
        }
        ExprKind::Call(Func::Abs, args) => args.first().map_or(U::Unknown, |a| measure(a, env)),
        ExprKind::Call(_, args) => match args.as_slice() {
            [a, b] => compare(measure(a, env), measure(b, env)).0,
            _ => U::Unknown,
        },
    }
}

/// Whether two measures have the same size of unit.
fn same_size(a: Measure, b: Measure) -> bool {
    (a.factor - b.factor).abs() <= 1e-9 * a.factor.abs().max(b.factor.abs())
}

/// A bare literal read in `m`: a finding unless it is 0 or `m` is a plain number.
fn bare_read(lit: Option<(f64, Span)>, m: Measure) -> Option<Finding> {
    let (v, span) = lit?;
    (v != 0.0 && m.dims != Dims::NONE).then_some(Finding::BareRead(v, span, m))
}

/// Two sides of `+` or `-`: the sum's unit and what is wrong.
fn add(op: BinOp, a: U, b: U) -> (U, Option<Finding>) {
    let verb = if op == BinOp::Add {
        "adds"
    } else {
        "subtracts"
    };
    let (a, b, f) = unscale(a, b);
    if f.is_some() {
        return (a, f);
    }
    match (a, b) {
        // `unscale` leaves no scaled side.
        (U::Unknown | U::Scaled(..), _) | (_, U::Unknown | U::Scaled(..)) => (U::Unknown, None),
        (U::Bare(_), U::Bare(_)) => (U::Bare(None), None),
        (U::Known(m), U::Bare(l)) | (U::Bare(l), U::Known(m)) => {
            if m.instant {
                let f = l.map(|(v, s)| Finding::InstantPlusBare(v, s, m));
                (U::Known(m), f)
            } else {
                (U::Known(m), bare_read(l, m))
            }
        }
        (U::Flex(d), U::Bare(l)) | (U::Bare(l), U::Flex(d)) => {
            (U::Flex(d), bare_read(l, Measure::base(d)))
        }
        (U::Flex(x), U::Flex(y)) => {
            if x == y {
                (U::Flex(x), None)
            } else {
                let m = format!("this {verb} {} and {}", x.describe(), y.describe());
                (U::Unknown, Some(Finding::Mismatch(m)))
            }
        }
        (U::Known(m), U::Flex(d)) | (U::Flex(d), U::Known(m)) => {
            if m.dims == d {
                (U::Known(m), None)
            } else {
                let m = format!("this {verb} {} and {}", m.describe(), d.describe());
                (U::Unknown, Some(Finding::Mismatch(m)))
            }
        }
        (U::Known(x), U::Known(y)) => {
            if x.dims != y.dims || !same_size(x, y) {
                let m = format!("this {verb} {} and {}", x.describe(), y.describe());
                return (U::Unknown, Some(Finding::Mismatch(m)));
            }
            match (x.instant, y.instant, op) {
                (true, true, BinOp::Sub) => (U::Known(x.as_duration()), None),
                (true, true, _) => {
                    let m = "this adds two instants: subtract them for the time between".into();
                    (U::Unknown, Some(Finding::Mismatch(m)))
                }
                (false, true, _) => (U::Known(y), None),
                _ => (U::Known(x), None),
            }
        }
    }
}

/// Two sides of a comparison (or of `min`/`max`): the unit they share and what is wrong.
fn compare(a: U, b: U) -> (U, Option<Finding>) {
    let (a, b, f) = unscale(a, b);
    if f.is_some() {
        return (a, f);
    }
    match (a, b) {
        (U::Known(m), U::Bare(l)) | (U::Bare(l), U::Known(m)) => {
            // A frame number is an instant's own name (`T >= 0`); a duration or any other
            // unit is read as said.
            let f = if m.instant { None } else { bare_read(l, m) };
            (U::Known(m), f)
        }
        (U::Known(x), U::Known(y)) if x.dims == y.dims && !same_size(x, y) => {
            let m = format!(
                "this compares {} with {}: the same kind of quantity in different units",
                x.describe(),
                y.describe()
            );
            (U::Unknown, Some(Finding::Mismatch(m)))
        }
        (U::Known(x), U::Known(y)) if x.dims == y.dims => (U::Known(x), None),
        (U::Known(x), U::Known(y)) => {
            let m = format!("this compares {} with {}", x.describe(), y.describe());
            (U::Unknown, Some(Finding::Mismatch(m)))
        }
        (x, y) => match add(BinOp::Sub, x, y) {
            (u, Some(Finding::Mismatch(m))) => (
                u,
                Some(Finding::Mismatch(m.replace("subtracts", "compares"))),
            ),
            other => other,
        },
    }
}

/// Two sides of `*` or `/`.
fn mul(op: BinOp, a: U, b: U) -> U {
    let m = |u: U| match u {
        U::Known(m) if m.instant => None,
        u => u.measure(),
    };
    match (a, b) {
        (U::Bare(_), U::Bare(_)) => U::Bare(None),
        (U::Bare(Some(l)), U::Known(x)) if op == BinOp::Mul && !x.instant => U::Scaled(x, l, false),
        (U::Known(x), U::Bare(Some(l))) if !x.instant => U::Scaled(x, l, op == BinOp::Div),
        (U::Bare(_), u) if op == BinOp::Mul => m(u).map_or(U::Unknown, U::Known),
        (U::Bare(_), u) => m(u).map_or(U::Unknown, |x| {
            U::Known(Measure {
                dims: Dims::NONE.over(x.dims),
                factor: 1.0 / x.factor,
                instant: false,
            })
        }),
        (u, U::Bare(_)) => m(u).map_or(U::Unknown, U::Known),
        (x, y) => match (m(x), m(y)) {
            (Some(x), Some(y)) => U::Known(if op == BinOp::Mul {
                Measure {
                    dims: x.dims.times(y.dims),
                    factor: x.factor * y.factor,
                    instant: false,
                }
            } else {
                Measure {
                    dims: x.dims.over(y.dims),
                    factor: x.factor / y.factor,
                    instant: false,
                }
            }),
            _ => U::Unknown,
        },
    }
}

/// Sets each quantity's `read_as` in the unit of its place, collecting findings.
struct Settle<'a> {
    env: &'a Env,
    cols: &'a Columns,
    found: &'a mut Vec<(Span, Finding)>,
}

impl Settle<'_> {
    fn literal(&mut self, l: &mut Literal) {
        match l {
            Literal::Pos(a) | Literal::Neg(a, _) => {
                for (i, arg) in a.args.iter_mut().enumerate() {
                    let want = column(&a.pred, i, self.cols);
                    if let (Some(w), U::Flex(d)) = (want, measure(arg, self.env)) {
                        if w.dims != d {
                            let m = format!(
                                "column {} of `{}` is {}, found {}",
                                i + 1,
                                a.pred,
                                w.describe(),
                                d.describe()
                            );
                            self.found.push((arg.span, Finding::Mismatch(m)));
                        }
                    }
                    self.settle(arg, want);
                }
            }
            Literal::Cmp(cmp) => {
                let (ul, ur) = (measure(&cmp.lhs, self.env), measure(&cmp.rhs, self.env));
                if let (_, Some(f)) = compare(ul, ur) {
                    self.found.push((cmp.span, f));
                }
                self.settle(&mut cmp.lhs, known(ur));
                self.settle(&mut cmp.rhs, known(ul));
            }
            Literal::Agg(g) => {
                if let Some(t) = &mut g.target {
                    self.settle(t, None);
                }
                for l in &mut g.body {
                    self.literal(l);
                }
            }
        }
    }

    /// Reads the quantities of `e` in `want` (where its dimensions are `want`'s).
    fn settle(&mut self, e: &mut Expr, want: Option<Measure>) {
        let span = e.span;
        match &mut e.kind {
            ExprKind::Quantity(q) => read_quantity(q, want),
            ExprKind::Neg(x) => self.settle(x, want),
            ExprKind::Call(Func::Abs, args) => {
                for a in args {
                    self.settle(a, want);
                }
            }
            ExprKind::Call(_, args) => {
                let us: Vec<U> = args.iter().map(|a| measure(a, self.env)).collect();
                if let [a, b] = us[..] {
                    if let (_, Some(f)) = compare(a, b) {
                        self.found.push((span, f));
                    }
                }
                let shared = us.iter().find_map(|u| known(*u)).or(want);
                for a in args {
                    self.settle(a, shared);
                }
            }
            ExprKind::Binary(op @ (BinOp::Add | BinOp::Sub), a, b) => {
                let (ua, ub) = (measure(a, self.env), measure(b, self.env));
                if let (_, Some(f)) = add(*op, ua, ub) {
                    self.found.push((span, f));
                }
                self.settle(a, known(ub).or(want));
                self.settle(b, known(ua).or(want));
            }
            ExprKind::Binary(_, a, b) => {
                let scaled = want.is_some_and(|w| !same_size(w, Measure::base(w.dims)));
                if scaled && (has_quantity(a) || has_quantity(b)) {
                    let m = "a product or quotient of quantities where a time in frames is \
                             meant: write the duration as one quantity (`3 s`)";
                    self.found.push((span, Finding::Mismatch(m.into())));
                }
                self.settle(a, None);
                self.settle(b, None);
            }
            ExprKind::Var(_)
            | ExprKind::Wildcard
            | ExprKind::Str(_)
            | ExprKind::Int(_)
            | ExprKind::Float(_) => {}
        }
    }
}

/// The measure of a side whose unit is known.
fn known(u: U) -> Option<Measure> {
    match u {
        U::Known(m) => Some(m),
        _ => None,
    }
}

fn has_quantity(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Quantity(_) => true,
        ExprKind::Neg(x) => has_quantity(x),
        ExprKind::Binary(_, a, b) => has_quantity(a) || has_quantity(b),
        ExprKind::Call(_, args) => args.iter().any(has_quantity),
        _ => false,
    }
}

/// A quantity read in `want` (a duration where `want` is an instant) when it has `want`'s
/// dimensions, else in base units; a whole number of frames is an integer.
fn read_quantity(q: &mut Quantity, want: Option<Measure>) {
    let Some(m) = q.measure() else { return };
    let target = match want {
        Some(w) if w.dims == m.dims => w.as_duration(),
        _ => Measure::base(m.dims),
    };
    let v = q.value * m.factor / target.factor;
    let frames = target.dims == Dims::TIME
        && same_size(
            target,
            Measure {
                factor: FRAME_S,
                ..target
            },
        );
    q.read_as = Some(
        if frames && (v - v.round()).abs() < 1e-6 && v.abs() < 1e15 {
            Number::Int(v.round() as i64)
        } else {
            Number::Float(v)
        },
    );
}

/// A number as a literal: at most six decimals, no trailing zeros.
fn number_text(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// The unit of a measure as a literal's unit, where one can be written.
fn literal_symbol(m: Measure) -> Option<&'static str> {
    if !same_size(m, Measure::base(m.dims)) {
        return None;
    }
    Some(match m.dims {
        Dims::LENGTH => "m",
        Dims::TIME => "s",
        Dims::SPEED => "m/s",
        Dims::ACCEL => "m/s2",
        Dims::ANGLE => "deg",
        Dims::ANGULAR_RATE => "deg/s",
        _ => return None,
    })
}

fn report(span: Span, f: Finding) -> Diagnostic {
    match f {
        Finding::Mismatch(m) => error(
            diagnostics::UNIT_MISMATCH,
            span,
            format!("unit mismatch: {m}"),
        )
        .with_hint(
            "both sides of a comparison, a sum or a difference must measure the same thing; \
                 write numbers with their unit (`50 km/h`, `3 s`, `0.3 rad/s`) and the checker \
                 converts them",
        ),
        Finding::BareRead(v, span, m) => {
            let read = readable(v, m);
            let d = warning(
                diagnostics::BARE_NUMBER,
                span,
                format!("`{}` has no unit and is read as {read}", number_text(v)),
            );
            if m.dims == Dims::TIME && !same_size(m, Measure::base(Dims::TIME)) {
                let secs = format!("{} s", number_text(v * m.factor));
                d.with_hint(format!("write the duration in seconds: `{secs}`"))
                    .with_edit(span, secs)
            } else if let Some(sym) = literal_symbol(m) {
                let n = number_text(v);
                let other = match m.dims {
                    Dims::SPEED => format!(" or `{n} km/h`"),
                    Dims::ANGULAR_RATE => format!(" or `{n} rad/s`"),
                    Dims::ANGLE => format!(" or `{n} rad`"),
                    _ => String::new(),
                };
                d.with_hint(format!(
                    "write the unit you mean: `{n} {sym}` (this reading){other}"
                ))
                .with_edit(Span::new(span.end, span.end), format!(" {sym}"))
            } else {
                d.with_hint("write the unit you mean")
            }
        }
        Finding::UnitlessFactor(v, span, need, have, meets) => {
            let n = number_text(v);
            let d = warning(
                diagnostics::BARE_NUMBER,
                span,
                format!(
                    "`{n}` has no unit, so this is {} where {} is meant",
                    have.describe(),
                    meets.describe()
                ),
            );
            match literal_symbol(Measure::base(need)) {
                Some(sym) => d
                    .with_hint(format!(
                        "write the unit `{n}` has: `{n} {sym}` ({})",
                        need.describe()
                    ))
                    .with_edit(Span::new(span.end, span.end), format!(" {sym}")),
                None => d.with_hint(format!("`{n}` needs a unit of {}", need.describe())),
            }
        }
        Finding::InstantPlusBare(v, span, m) => {
            let secs = format!("{} s", number_text(v * m.factor));
            error(
                diagnostics::INSTANT_PLUS_NUMBER,
                span,
                format!(
                    "a bare number added to a time: `{}` is read as {} (frames are not \
                     samples: in a 2 Hz log `T + 1` is no sample)",
                    number_text(v),
                    readable(v, m.as_duration()),
                ),
            )
            .with_hint(format!(
                "write the duration with its unit: `{secs}` (this reading), e.g. `T + 1 s`"
            ))
            .with_edit(span, secs)
        }
    }
}
