//! The recursive-descent parser: tokens to [`Program`], with error recovery.
//!
//! After a syntax error the parser skips to the next `.` at clause level and continues, so one
//! run reports every broken clause.

use scenalog_facts::catalog::ColType;
use scenalog_facts::units;

use crate::ast::*;
use crate::diagnostics::{self, error};
use crate::lexer::{lex, Tok, Token};
use crate::Diagnostic;

/// What the parser found besides the program: syntax diagnostics, and the names of predicates
/// whose clauses failed to parse (so the checker does not also call them unknown).
#[derive(Debug, Clone, Default)]
pub struct ParseOutput {
    /// The program (clauses that failed to parse are left out).
    pub program: Program,
    /// Syntax errors in source order.
    pub diagnostics: Vec<Diagnostic>,
    /// Head predicate names of clauses that failed to parse.
    pub broken_heads: Vec<String>,
}

/// Parses a program. Never panics; clauses with syntax errors are left out of the program.
pub fn parse(source: &str) -> (Program, Vec<Diagnostic>) {
    let out = parse_detailed(source);
    (out.program, out.diagnostics)
}

/// Parses a program, also returning the heads of broken clauses.
pub fn parse_detailed(source: &str) -> ParseOutput {
    let (toks, description) = lex(source);
    let mut p = Parser {
        toks,
        pos: 0,
        diags: Vec::new(),
        depth: 0,
    };
    let mut program = Program {
        description,
        ..Program::default()
    };
    let mut broken_heads = Vec::new();
    let mut stray_run = false;
    while !matches!(p.peek(), Tok::Eof) {
        let start = p.pos;
        let is_decl =
            matches!(p.peek(), Tok::Dot) && matches!(p.peek_at(1), Tok::Ident(s) if *s == "decl");
        let result = if is_decl {
            p.decl().map(|d| program.decls.push(d))
        } else {
            p.clause().map(|c| program.clauses.push(c))
        };
        if let Err(d) = result {
            // A run of stray tokens where clauses should start is reported once.
            let stray = p.pos == start;
            if !(stray && stray_run) {
                p.diags.push(*d);
            }
            stray_run = stray;
            if !is_decl {
                if let (Tok::Ident(name), Tok::LParen) =
                    (&p.toks[start].tok, p.peek_tok_at(start + 1))
                {
                    broken_heads.push(name.to_string());
                }
            }
            p.recover(start);
        } else {
            stray_run = false;
        }
    }
    ParseOutput {
        program,
        diagnostics: p.diags,
        broken_heads,
    }
}

type PResult<T> = Result<T, Box<Diagnostic>>;

/// Nesting limit of the parser's own recursion (parentheses, unary minus, function calls,
/// aggregates), so hostile input cannot overflow the stack: 64 levels parse, more than 64 is
/// E0002. Each parenthesis, sign, call and aggregate around a part is one level.
pub const MAX_DEPTH: usize = 64;

/// Height limit of an expression tree, in nested operators. A chain `A + B + C + …` is a tree as tall as it is long,
/// and every later stage (checker, planner, evaluator, printer, explanations) walks expression
/// trees recursively; bounding their height here bounds all of those walks.
pub const MAX_EXPR_HEIGHT: usize = 128;

/// The height of an expression tree in operators (a variable or constant has height 0;
/// `A + B` has 1), computed without recursion.
pub fn expr_height(e: &Expr) -> usize {
    let mut stack = vec![(e, 0usize)];
    let mut height = 0;
    while let Some((e, h)) = stack.pop() {
        height = height.max(h);
        match &e.kind {
            ExprKind::Neg(a) => stack.push((a, h + 1)),
            ExprKind::Binary(_, a, b) => {
                stack.push((a, h + 1));
                stack.push((b, h + 1));
            }
            ExprKind::Call(_, args) => stack.extend(args.iter().map(|a| (a, h + 1))),
            _ => {}
        }
    }
    height
}

struct Parser<'a> {
    toks: Vec<Token<'a>>,
    pos: usize,
    diags: Vec<Diagnostic>,
    depth: usize,
}

fn is_agg_keyword(s: &str) -> bool {
    matches!(s, "count" | "min" | "max" | "sum")
}

fn builtin(s: &str) -> Option<Func> {
    match s {
        "abs" => Some(Func::Abs),
        "min" => Some(Func::Min),
        "max" => Some(Func::Max),
        _ => None,
    }
}

impl<'a> Parser<'a> {
    fn peek(&self) -> &Tok<'a> {
        self.peek_at(0)
    }

    fn peek_at(&self, k: usize) -> &Tok<'a> {
        self.peek_tok_at(self.pos + k)
    }

    fn peek_tok_at(&self, i: usize) -> &Tok<'a> {
        let last = self.toks.len() - 1;
        &self.toks[i.min(last)].tok
    }

    fn span(&self) -> Span {
        let last = self.toks.len() - 1;
        self.toks[self.pos.min(last)].span
    }

    fn prev_span(&self) -> Span {
        self.toks[self.pos.saturating_sub(1)].span
    }

    /// Moves past the current token, returning its span.
    fn bump(&mut self) -> Span {
        let last = self.toks.len() - 1;
        let span = self.toks[self.pos.min(last)].span;
        if self.pos < last {
            self.pos += 1;
        }
        span
    }

    fn eat(&mut self, t: &Tok) -> bool {
        if self.peek() == t {
            self.bump();
            true
        } else {
            false
        }
    }

    /// An E0001 "expected …, found …" at the current token.
    fn unexpected(&self, expected: &str) -> Box<Diagnostic> {
        let found = self.peek();
        let span = self.span();
        let mut d = match found {
            Tok::Error(m) => error(diagnostics::SYNTAX, span, format!("syntax error: {m}")),
            _ => error(
                diagnostics::SYNTAX,
                span,
                format!(
                    "syntax error: expected {expected}, found {}",
                    found.describe()
                ),
            ),
        };
        d.hint = match found {
            Tok::Ident(s) if expected.contains("term") || expected.contains("expression") => Some(format!(
                "variables start with a capital letter or `_` (write `{}`), strings are quoted (write \"{s}\")",
                capitalise(s)
            )),
            Tok::Eof => Some("every clause ends with `.`".into()),
            Tok::Eq if matches!(self.peek_tok_at(self.pos.wrapping_sub(1)), Tok::Eq) => {
                Some("equality is a single `=`".into())
            }
            Tok::Error(_) => None,
            _ if expected.contains("`.`") => Some(
                "a clause is `head(Args) :- literal, literal, … .`: literals are separated by `,` and the clause ends with `.`"
                    .into(),
            ),
            _ => None,
        };
        Box::new(d)
    }

    fn expect(&mut self, t: &Tok, what: &str) -> PResult<Span> {
        if self.peek() == t {
            Ok(self.bump())
        } else {
            Err(self.unexpected(what))
        }
    }

    /// Skips to just after the next `.` at clause level (or to a `.decl`), making progress. A stray
    /// token where a clause should start is skipped alone, so the clause after it still parses.
    fn recover(&mut self, start: usize) {
        if self.pos == start {
            self.bump();
            return;
        }
        loop {
            match self.peek() {
                Tok::Eof => return,
                Tok::Dot => {
                    if matches!(self.peek_at(1), Tok::Ident(s) if *s == "decl") {
                        return;
                    }
                    self.bump();
                    return;
                }
                _ => {
                    self.bump();
                }
            }
        }
    }

    fn decl(&mut self) -> PResult<Decl> {
        let start = self.bump(); // `.`
        self.bump(); // `decl`
        let (name, name_span) = match self.peek().clone() {
            Tok::Ident(n) => (n, self.bump()),
            _ => return Err(self.unexpected("a predicate name after `.decl`")),
        };
        self.expect(&Tok::LParen, "`(`")?;
        let mut columns = Vec::new();
        let mut units = Vec::new();
        if !self.eat(&Tok::RParen) {
            loop {
                let col = match self.peek().clone() {
                    Tok::Var(v) => v,
                    Tok::Ident(v) => v,
                    _ => return Err(self.unexpected("a column name")),
                };
                self.bump();
                self.expect(&Tok::Colon, "`:` and a type after the column name")?;
                let ty = match self.peek().clone() {
                    Tok::Ident(t) => match ColType::parse(t) {
                        Some(ty) => ty,
                        None => {
                            let d = error(
                                diagnostics::SYNTAX,
                                self.span(),
                                format!("syntax error: unknown column type `{t}`"),
                            )
                            .with_hint("column types are track, time, lane, str, float and int");
                            return Err(Box::new(d));
                        }
                    },
                    _ => {
                        return Err(
                            self.unexpected("a column type (track, time, lane, str, float, int)")
                        )
                    }
                };
                self.bump();
                units.push(self.decl_unit()?);
                columns.push((col.to_string(), ty));
                if self.eat(&Tok::Comma) {
                    continue;
                }
                self.expect(&Tok::RParen, "`,` or `)`")?;
                break;
            }
        }
        // An optional `.` after a declaration, unless it starts the next `.decl`.
        if matches!(self.peek(), Tok::Dot)
            && !matches!(self.peek_at(1), Tok::Ident(s) if *s == "decl")
        {
            self.bump();
        }
        Ok(Decl {
            name: name.to_string(),
            name_span,
            columns,
            units,
            span: start.to(self.prev_span()),
        })
    }

    fn clause(&mut self) -> PResult<Clause> {
        let head = match self.peek() {
            Tok::Ident(_) => self.atom()?,
            _ => return Err(self.unexpected("a clause (a predicate name like `referred`)")),
        };
        let mut body = Vec::new();
        if self.eat(&Tok::If) {
            body = self.body(&Tok::Dot)?;
        }
        let end = self.expect(
            &Tok::Dot,
            if body.is_empty() {
                "`:-` or `.`"
            } else {
                "`,` or `.`"
            },
        )?;
        Ok(Clause {
            span: head.span.to(end),
            head,
            body,
        })
    }

    /// Literals separated by commas, up to (not including) `end`.
    fn body(&mut self, end: &Tok) -> PResult<Vec<Literal>> {
        let mut body = vec![self.literal()?];
        while self.eat(&Tok::Comma) {
            body.push(self.literal()?);
        }
        if self.peek() != end {
            let what = if *end == Tok::Dot {
                "`,` or `.`"
            } else {
                "`,` or `}`"
            };
            return Err(self.unexpected(what));
        }
        Ok(body)
    }

    fn atom(&mut self) -> PResult<Atom> {
        let (pred, pred_span) = match self.peek().clone() {
            Tok::Ident(n) => (n, self.bump()),
            _ => return Err(self.unexpected("a predicate name")),
        };
        let mut args = Vec::new();
        let mut end = pred_span;
        if self.eat(&Tok::LParen) {
            if !matches!(self.peek(), Tok::RParen) {
                loop {
                    args.push(self.expr()?);
                    if !self.eat(&Tok::Comma) {
                        break;
                    }
                }
            }
            end = self.expect(&Tok::RParen, "`,` or `)`")?;
        }
        Ok(Atom {
            pred: pred.to_string(),
            pred_span,
            args,
            span: pred_span.to(end),
        })
    }

    fn literal(&mut self) -> PResult<Literal> {
        let negation = match self.peek() {
            Tok::Bang => true,
            Tok::Ident(s) => *s == "not" && matches!(self.peek_at(1), Tok::Ident(_)),
            _ => false,
        };
        if negation {
            let start = self.bump();
            if !matches!(self.peek(), Tok::Ident(_)) {
                return Err(self.unexpected("an atom after `!`"));
            }
            let a = self.atom()?;
            let span = start.to(a.span);
            return Ok(Literal::Neg(a, span));
        }
        let is_atom = match self.peek() {
            Tok::Ident(s) => !(builtin(s).is_some() && matches!(self.peek_at(1), Tok::LParen)),
            _ => false,
        };
        if is_atom {
            Ok(Literal::Pos(self.atom()?))
        } else {
            self.comparison()
        }
    }

    fn comparison(&mut self) -> PResult<Literal> {
        let lhs = self.expr()?;
        let op = match self.peek() {
            Tok::Lt => CmpOp::Lt,
            Tok::Le => CmpOp::Le,
            Tok::Gt => CmpOp::Gt,
            Tok::Ge => CmpOp::Ge,
            Tok::Eq => CmpOp::Eq,
            Tok::Ne => CmpOp::Ne,
            _ => {
                return Err(
                    self.unexpected("a comparison operator (`<`, `<=`, `>`, `>=`, `=`, `!=`)")
                )
            }
        };
        self.bump();
        if op == CmpOp::Eq {
            if let Some(agg) = self.try_aggregate(&lhs)? {
                return Ok(Literal::Agg(agg));
            }
        }
        let rhs = self.expr()?;
        Ok(Literal::Cmp(Comparison {
            span: lhs.span.to(rhs.span),
            op,
            lhs,
            rhs,
        }))
    }

    /// After `lhs =`: an aggregate `count : { … }` or `min|max|sum E : { … }`, if one follows.
    fn try_aggregate(&mut self, lhs: &Expr) -> PResult<Option<Aggregate>> {
        let func = match self.peek() {
            Tok::Ident(s) if *s == "count" && matches!(self.peek_at(1), Tok::Colon) => {
                AggFunc::Count
            }
            Tok::Ident(s) if is_agg_keyword(s) && *s != "count" => match *s {
                "min" => AggFunc::Min,
                "max" => AggFunc::Max,
                _ => AggFunc::Sum,
            },
            _ => return Ok(None),
        };
        let save = (self.pos, self.diags.len());
        self.bump();
        let target = if func == AggFunc::Count {
            None
        } else {
            match self.expr() {
                Ok(e) if matches!(self.peek(), Tok::Colon) => Some(e),
                _ => {
                    // Not an aggregate: `min(A, B)` and friends are expressions.
                    self.pos = save.0;
                    self.diags.truncate(save.1);
                    return Ok(None);
                }
            }
        };
        self.expect(&Tok::Colon, "`:` after the aggregate")?;
        self.expect(&Tok::LBrace, "`{` to open the aggregate's body")?;
        self.enter()?;
        let body = self.body(&Tok::RBrace);
        self.depth -= 1;
        let body = body?;
        let end = self.expect(&Tok::RBrace, "`}`")?;
        Ok(Some(Aggregate {
            result: lhs.clone(),
            func,
            target,
            body,
            span: lhs.span.to(end),
        }))
    }

    fn enter(&mut self) -> PResult<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            self.depth -= 1;
            return Err(Box::new(
                error(
                    diagnostics::TOO_DEEP,
                    self.span(),
                    format!(
                        "parentheses, signs, calls or aggregates nest deeper than {MAX_DEPTH} levels"
                    ),
                )
                .with_hint("name the inner parts with bindings (`S = A + B`) or helper rules"),
            ));
        }
        Ok(())
    }

    /// An expression that is not inside another one (a comparison's side, an atom's argument, an
    /// aggregate's target): the nesting levels are those of the parentheses, signs, calls and
    /// aggregates around its parts.
    fn expr(&mut self) -> PResult<Expr> {
        self.additive()
    }

    /// An expression one level down: inside parentheses or a call's argument list.
    fn nested_expr(&mut self) -> PResult<Expr> {
        self.enter()?;
        let r = self.additive();
        self.depth -= 1;
        r
    }

    /// An E0002 when an operator chain makes an expression taller than [`MAX_EXPR_HEIGHT`].
    fn too_tall(&self, start: Span) -> Box<Diagnostic> {
        Box::new(
            error(
                diagnostics::TOO_DEEP,
                start.to(self.prev_span()),
                format!("this expression nests more than {MAX_EXPR_HEIGHT} operators deep"),
            )
            .with_hint(
                "split it with intermediate bindings, e.g. `S1 = A + B + C, S2 = S1 + D + E`",
            ),
        )
    }

    fn additive(&mut self) -> PResult<Expr> {
        let mut lhs = self.multiplicative()?;
        let mut height = expr_height(&lhs);
        loop {
            let op = match self.peek() {
                Tok::Plus => BinOp::Add,
                Tok::Minus => BinOp::Sub,
                _ => return Ok(lhs),
            };
            self.bump();
            let rhs = self.multiplicative()?;
            height = height.max(expr_height(&rhs)) + 1;
            if height > MAX_EXPR_HEIGHT {
                return Err(self.too_tall(lhs.span));
            }
            lhs = Expr {
                span: lhs.span.to(rhs.span),
                kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
            };
        }
    }

    fn multiplicative(&mut self) -> PResult<Expr> {
        let mut lhs = self.unary()?;
        let mut height = expr_height(&lhs);
        loop {
            let op = match self.peek() {
                Tok::Star => BinOp::Mul,
                Tok::Slash => BinOp::Div,
                Tok::Ident("mod") => BinOp::Mod,
                _ => return Ok(lhs),
            };
            self.bump();
            let rhs = self.unary()?;
            height = height.max(expr_height(&rhs)) + 1;
            if height > MAX_EXPR_HEIGHT {
                return Err(self.too_tall(lhs.span));
            }
            lhs = Expr {
                span: lhs.span.to(rhs.span),
                kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)),
            };
        }
    }

    fn unary(&mut self) -> PResult<Expr> {
        if matches!(self.peek(), Tok::Minus) {
            let start = self.bump();
            // `-` directly before a number is a negative constant (not before a power:
            // `-2 ^ 2` is -(2 ^ 2)).
            let power = matches!(self.peek_at(1), Tok::Caret);
            match self.peek().clone() {
                _ if power => {}
                Tok::Int(text) if self.span().start == start.end => {
                    let span = start.to(self.bump());
                    let e = int_literal(&format!("-{text}"), span)?;
                    return self.unit_suffix(e);
                }
                Tok::Float(text) if self.span().start == start.end => {
                    let span = start.to(self.bump());
                    let e = float_literal(&format!("-{text}"), span)?;
                    return self.unit_suffix(e);
                }
                _ => {}
            }
            self.enter()?;
            let inner = self.unary();
            self.depth -= 1;
            let inner = inner?;
            if expr_height(&inner) + 1 > MAX_EXPR_HEIGHT {
                return Err(self.too_tall(start));
            }
            return Ok(Expr {
                span: start.to(inner.span),
                kind: ExprKind::Neg(Box::new(inner)),
            });
        }
        self.power()
    }

    /// `primary ^ unary`: power, right-associative (`2 ^ 3 ^ 2` is 2 ^ 9) and above a sign.
    fn power(&mut self) -> PResult<Expr> {
        let base = self.primary()?;
        if !matches!(self.peek(), Tok::Caret) {
            return Ok(base);
        }
        self.bump();
        self.enter()?;
        let exponent = self.unary();
        self.depth -= 1;
        let exponent = exponent?;
        if expr_height(&base).max(expr_height(&exponent)) + 1 > MAX_EXPR_HEIGHT {
            return Err(self.too_tall(base.span));
        }
        Ok(Expr {
            span: base.span.to(exponent.span),
            kind: ExprKind::Binary(BinOp::Pow, Box::new(base), Box::new(exponent)),
        })
    }

    fn primary(&mut self) -> PResult<Expr> {
        let span = self.span();
        let kind = match self.peek().clone() {
            Tok::Var(v) => ExprKind::Var(v.to_string()),
            Tok::Wildcard => ExprKind::Wildcard,
            Tok::Str(s) => ExprKind::Str(s),
            Tok::Int(text) => {
                self.bump();
                let e = int_literal(text, span)?;
                return self.unit_suffix(e);
            }
            Tok::Float(text) => {
                self.bump();
                let e = float_literal(text, span)?;
                return self.unit_suffix(e);
            }
            Tok::LParen => {
                self.bump();
                let inner = self.nested_expr()?;
                let end = self.expect(&Tok::RParen, "`)`")?;
                return Ok(Expr {
                    kind: inner.kind,
                    span: span.to(end),
                });
            }
            Tok::Ident(name)
                if builtin(name).is_some() && matches!(self.peek_at(1), Tok::LParen) =>
            {
                let func = builtin(name).unwrap_or(Func::Abs);
                self.bump();
                self.bump();
                let mut args = Vec::new();
                if !matches!(self.peek(), Tok::RParen) {
                    loop {
                        args.push(self.nested_expr()?);
                        if !self.eat(&Tok::Comma) {
                            break;
                        }
                    }
                }
                let end = self.expect(&Tok::RParen, "`,` or `)`")?;
                let want = if func == Func::Abs { 1 } else { 2 };
                if args.len() != want {
                    return Err(Box::new(
                        error(
                            diagnostics::SYNTAX,
                            span.to(end),
                            format!(
                                "syntax error: `{}` takes {want} argument{}, found {}",
                                func.as_str(),
                                if want == 1 { "" } else { "s" },
                                args.len()
                            ),
                        )
                        .with_hint("abs(E), min(E1, E2), max(E1, E2)"),
                    ));
                }
                if args.iter().map(expr_height).max().unwrap_or(0) + 1 > MAX_EXPR_HEIGHT {
                    return Err(self.too_tall(span));
                }
                return Ok(Expr {
                    kind: ExprKind::Call(func, args),
                    span: span.to(end),
                });
            }
            _ => {
                return Err(self
                    .unexpected("a term (a variable, `_`, a string, a number or an expression)"))
            }
        };
        self.bump();
        Ok(Expr { kind, span })
    }
}

impl Parser<'_> {
    /// The unit after a `.decl` column's type, `<m/s>`, if any: one unit name or a quotient of
    /// two, as a literal's.
    fn decl_unit(&mut self) -> PResult<Option<String>> {
        if !matches!(self.peek(), Tok::Lt) {
            return Ok(None);
        }
        let start = self.bump();
        let mut text = String::new();
        loop {
            match self.peek().clone() {
                Tok::Ident(w) => text.push_str(w),
                Tok::Slash => text.push('/'),
                Tok::Gt => break,
                _ => return Err(self.unexpected("a unit and `>` (e.g. `float<m/s>`)")),
            }
            self.bump();
        }
        let end = self.bump();
        match units::parse_unit(&text) {
            // A column holds its numbers in the base unit of their kind, as the catalog does.
            Some(m) if (m.factor - 1.0).abs() < 1e-12 => Ok(Some(text)),
            found => Err(Box::new(
                error(
                    diagnostics::SYNTAX,
                    start.to(end),
                    match found {
                        Some(_) => format!(
                            "syntax error: a column's unit is the base unit of its kind, not `{text}`"
                        ),
                        None => format!("syntax error: `{text}` is not a unit"),
                    },
                )
                .with_hint(
                    "a column holds m, m/s, m/s2, deg, deg/s or s (`float<m/s>`); write other \
                     units in the numbers compared with it (`S > 50 km/h`)",
                ),
            )),
        }
    }

    /// A number followed by a unit (`50 km/h`, `3 s`, `0.3 rad/s`) becomes a quantity; a
    /// lowercase word after a number that is not a unit is an error listing the units.
    fn unit_suffix(&mut self, number: Expr) -> PResult<Expr> {
        let value = match number.kind {
            ExprKind::Int(i) => i as f64,
            ExprKind::Float(f) => f,
            _ => return Ok(number),
        };
        let Tok::Ident(first) = self.peek().clone() else {
            return Ok(number);
        };
        if matches!(self.peek_at(1), Tok::LParen) {
            return Ok(number);
        }
        if first == "mod" {
            // `7 mod 2`: the operator, not a unit.
            return Ok(number);
        }
        if units::literal_unit(first).is_none() {
            return Err(Box::new(unknown_unit(first, self.span())));
        }
        let mut unit = first.to_string();
        self.bump();
        if matches!(self.peek(), Tok::Slash) {
            if let Tok::Ident(den) = self.peek_at(1).clone() {
                if !matches!(self.peek_at(2), Tok::LParen) {
                    self.bump();
                    if units::literal_unit(den).is_none() {
                        return Err(Box::new(unknown_unit(den, self.span())));
                    }
                    self.bump();
                    unit = format!("{unit}/{den}");
                }
            }
        }
        let end = self.prev_span();
        Ok(Expr {
            span: number.span.to(end),
            kind: ExprKind::Quantity(Quantity {
                value,
                unit,
                read_as: None,
            }),
        })
    }
}

/// E0001 for a word after a number that is not a unit.
fn unknown_unit(word: &str, span: Span) -> Diagnostic {
    let names: Vec<&str> = units::LITERAL_UNITS.iter().map(|u| u.name).collect();
    error(
        diagnostics::SYNTAX,
        span,
        format!("syntax error: `{word}` after a number is not a unit"),
    )
    .with_hint(format!(
        "a number may carry a unit: {}, or a quotient of two (`km/h`, `rad/s`, `m/s2`)",
        names.join(", ")
    ))
}

fn int_literal(text: &str, span: Span) -> PResult<Expr> {
    match text.parse::<i64>() {
        Ok(v) => Ok(Expr {
            kind: ExprKind::Int(v),
            span,
        }),
        Err(_) => Err(Box::new(
            error(
                diagnostics::SYNTAX,
                span,
                format!("syntax error: the integer `{text}` does not fit in 64 bits"),
            )
            .with_hint("write it as a float, e.g. `1.0e20`"),
        )),
    }
}

fn float_literal(text: &str, span: Span) -> PResult<Expr> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(Expr {
            kind: ExprKind::Float(v),
            span,
        }),
        _ => Err(Box::new(error(
            diagnostics::SYNTAX,
            span,
            format!("syntax error: the number `{text}` is out of range"),
        ))),
    }
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect(),
        None => String::new(),
    }
}
