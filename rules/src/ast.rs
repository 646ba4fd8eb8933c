//! The abstract syntax tree of a Scenalog program. Every node carries the byte span it came from.
//!
//! This is the contract between the parser, the checker, the pretty-printer and the engine:
//! plain data, no behaviour beyond small accessors.

use scenalog_facts::catalog::ColType;

/// A half-open byte range `start..end` into the program text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Span {
    /// First byte.
    pub start: usize,
    /// One past the last byte.
    pub end: usize,
}

impl Span {
    /// A span from `start` to `end`.
    pub fn new(start: usize, end: usize) -> Span {
        Span { start, end }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }
}

/// A whole program: its description, declarations and clauses in source order.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Program {
    /// The text of a leading `// description: …` comment, trimmed.
    pub description: Option<String>,
    /// `.decl` lines.
    pub decls: Vec<Decl>,
    /// Rules and ground facts.
    pub clauses: Vec<Clause>,
}

/// `.decl name(Col: type, …)`: declares a helper predicate's column names and types.
#[derive(Debug, Clone, PartialEq)]
pub struct Decl {
    /// The predicate name.
    pub name: String,
    /// Span of the name.
    pub name_span: Span,
    /// Column names and types.
    pub columns: Vec<(String, ColType)>,
    /// The unit written after a column's type (`V: float<m/s>`, as `scenalog catalog` prints
    /// signatures), one entry per column.
    pub units: Vec<Option<String>>,
    /// Span of the whole declaration.
    pub span: Span,
}

/// `head :- body.` or, with an empty body, the ground fact `head.`.
#[derive(Debug, Clone, PartialEq)]
pub struct Clause {
    /// The head atom.
    pub head: Atom,
    /// Body literals in source order (empty for a fact).
    pub body: Vec<Literal>,
    /// Span of the whole clause, up to and including the final `.`.
    pub span: Span,
}

impl Clause {
    /// Whether the clause is a ground fact (no body).
    pub fn is_fact(&self) -> bool {
        self.body.is_empty()
    }
}

/// `pred(arg, …)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Atom {
    /// Predicate name.
    pub pred: String,
    /// Span of the predicate name.
    pub pred_span: Span,
    /// Arguments (expressions; usually variables or constants).
    pub args: Vec<Expr>,
    /// Span of the whole atom.
    pub span: Span,
}

/// One body literal.
#[derive(Debug, Clone, PartialEq)]
pub enum Literal {
    /// A positive atom.
    Pos(Atom),
    /// A negated atom (`!p(..)` or `not p(..)`); the span covers the negation sign too.
    Neg(Atom, Span),
    /// A comparison `lhs op rhs`; `X = expr` with `X` otherwise unbound is a binding.
    Cmp(Comparison),
    /// An aggregate `R = count : { … }` / `R = min E : { … }` / `max` / `sum`.
    Agg(Aggregate),
}

impl Literal {
    /// Span of the literal.
    pub fn span(&self) -> Span {
        match self {
            Literal::Pos(a) => a.span,
            Literal::Neg(_, s) => *s,
            Literal::Cmp(c) => c.span,
            Literal::Agg(a) => a.span,
        }
    }
}

/// Comparison operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CmpOp {
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `=`
    Eq,
    /// `!=`
    Ne,
}

impl CmpOp {
    /// The operator as written.
    pub fn as_str(self) -> &'static str {
        match self {
            CmpOp::Lt => "<",
            CmpOp::Le => "<=",
            CmpOp::Gt => ">",
            CmpOp::Ge => ">=",
            CmpOp::Eq => "=",
            CmpOp::Ne => "!=",
        }
    }

    /// The comparison with its sides swapped (`a < b` is `b > a`; `=` and `!=` stay).
    pub fn flipped(self) -> CmpOp {
        match self {
            CmpOp::Lt => CmpOp::Gt,
            CmpOp::Le => CmpOp::Ge,
            CmpOp::Gt => CmpOp::Lt,
            CmpOp::Ge => CmpOp::Le,
            other => other,
        }
    }
}

/// `lhs op rhs`.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The operator.
    pub op: CmpOp,
    /// Left operand.
    pub lhs: Expr,
    /// Right operand.
    pub rhs: Expr,
    /// Span of the whole comparison.
    pub span: Span,
}

/// Aggregate functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AggFunc {
    /// Number of distinct bindings of the body's variables.
    Count,
    /// Smallest value of the target expression.
    Min,
    /// Largest value of the target expression.
    Max,
    /// Sum of the target expression over distinct bindings.
    Sum,
}

impl AggFunc {
    /// The keyword.
    pub fn as_str(self) -> &'static str {
        match self {
            AggFunc::Count => "count",
            AggFunc::Min => "min",
            AggFunc::Max => "max",
            AggFunc::Sum => "sum",
        }
    }
}

/// `result = func [target] : { body }`. Variables of the body that also appear outside the
/// aggregate (in the clause's other literals or head) group it.
#[derive(Debug, Clone, PartialEq)]
pub struct Aggregate {
    /// The variable that receives the result.
    pub result: Expr,
    /// The function.
    pub func: AggFunc,
    /// The aggregated expression (`None` for `count`).
    pub target: Option<Expr>,
    /// The literals inside the braces.
    pub body: Vec<Literal>,
    /// Span of the whole aggregate literal.
    pub span: Span,
}

/// Binary arithmetic operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `mod`: the remainder of an integer division, with the dividend's sign (Soufflé's `%`;
    /// `%` starts a comment here).
    Mod,
    /// `^`: power (right-associative, binding tighter than a sign: `-2 ^ 2` is -4).
    Pow,
}

impl BinOp {
    /// The operator as written.
    pub fn as_str(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Mod => "mod",
            BinOp::Pow => "^",
        }
    }
}

/// Built-in functions usable in expressions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Func {
    /// `abs(E)`
    Abs,
    /// `min(E, E)`
    Min,
    /// `max(E, E)`
    Max,
}

impl Func {
    /// The name as written.
    pub fn as_str(self) -> &'static str {
        match self {
            Func::Abs => "abs",
            Func::Min => "min",
            Func::Max => "max",
        }
    }
}

/// A number written with a unit, `50 km/h`: the checker reads it in the unit of what it is
/// compared with, added to or stored in (`speed`'s m/s: 13.89; a frame's 0.1 s: `3 s` is 30).
#[derive(Debug, Clone, PartialEq)]
pub struct Quantity {
    /// The number as written.
    pub value: f64,
    /// The unit as written: one unit name or a quotient of two (`km/h`).
    pub unit: String,
    /// The number in the unit of its place, set by the checker (`None` before it ran).
    pub read_as: Option<Number>,
}

/// A plain number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    /// An integer (a count of frames, for a duration added to a frame).
    Int(i64),
    /// A float.
    Float(f64),
}

impl Number {
    /// The number as a float.
    pub fn as_f64(self) -> f64 {
        match self {
            Number::Int(i) => i as f64,
            Number::Float(f) => f,
        }
    }
}

impl Quantity {
    /// The measure its unit names.
    pub fn measure(&self) -> Option<scenalog_facts::units::Measure> {
        scenalog_facts::units::parse_unit(&self.unit)
    }

    /// The number the engine uses: as the checker read it, else in base units (m, s, deg).
    pub fn number(&self) -> Number {
        match self.read_as {
            Some(n) => n,
            None => Number::Float(self.value * self.measure().map_or(1.0, |m| m.factor)),
        }
    }
}

/// An expression (a term): a variable, a constant or arithmetic over them.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it is.
    pub span: Span,
}

/// The kinds of expressions.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// A named variable (`X`, `_name`).
    Var(String),
    /// The anonymous variable `_`.
    Wildcard,
    /// A string constant (unescaped contents).
    Str(String),
    /// An integer constant.
    Int(i64),
    /// A floating-point constant.
    Float(f64),
    /// A number with a unit (`50 km/h`, `3 s`).
    Quantity(Quantity),
    /// Unary minus.
    Neg(Box<Expr>),
    /// Binary arithmetic.
    Binary(BinOp, Box<Expr>, Box<Expr>),
    /// A built-in function call.
    Call(Func, Vec<Expr>),
}

impl Expr {
    /// The variable `name`, with no place in the source (for clauses a fix writes).
    pub fn var(name: &str) -> Expr {
        Expr {
            kind: ExprKind::Var(name.to_string()),
            span: Span::default(),
        }
    }

    /// The variable name if this is a plain named variable.
    pub fn as_var(&self) -> Option<&str> {
        match &self.kind {
            ExprKind::Var(v) => Some(v),
            _ => None,
        }
    }
}
