//! The pretty-printer: a [`Program`] to canonical text that parses back to the same AST.

use std::fmt::Write;

use crate::ast::*;

/// Prints a program in canonical form: the description comment, declarations, then one clause
/// per line with the body indented on following lines.
pub fn print_program(program: &Program) -> String {
    let mut out = String::new();
    if let Some(d) = &program.description {
        let _ = writeln!(out, "// description: {}", d.replace(['\n', '\r'], " "));
    }
    for d in &program.decls {
        out.push_str(&print_decl(d));
        out.push('\n');
    }
    for c in &program.clauses {
        out.push_str(&print_clause(c));
        out.push('\n');
    }
    out
}

/// `.decl name(Col: type, …)`.
pub fn print_decl(d: &Decl) -> String {
    let cols: Vec<String> = d
        .columns
        .iter()
        .enumerate()
        .map(|(i, (n, t))| match d.units.get(i).cloned().flatten() {
            Some(u) => format!("{n}: {t}<{u}>"),
            None => format!("{n}: {t}"),
        })
        .collect();
    format!(".decl {}({})", d.name, cols.join(", "))
}

/// One clause, ending with `.`.
pub fn print_clause(c: &Clause) -> String {
    let mut out = print_atom(&c.head);
    if !c.body.is_empty() {
        out.push_str(" :-\n");
        let lits: Vec<String> = c
            .body
            .iter()
            .map(|l| format!("    {}", print_literal(l)))
            .collect();
        out.push_str(&lits.join(",\n"));
    }
    out.push('.');
    out
}

/// `pred(arg, …)`, or `pred` with no arguments.
pub fn print_atom(a: &Atom) -> String {
    if a.args.is_empty() {
        return a.pred.clone();
    }
    let args: Vec<String> = a.args.iter().map(print_expr).collect();
    format!("{}({})", a.pred, args.join(", "))
}

/// One body literal.
pub fn print_literal(l: &Literal) -> String {
    match l {
        Literal::Pos(a) => print_atom(a),
        Literal::Neg(a, _) => format!("!{}", print_atom(a)),
        Literal::Cmp(c) => format!(
            "{} {} {}",
            print_expr(&c.lhs),
            c.op.as_str(),
            print_expr(&c.rhs)
        ),
        Literal::Agg(g) => {
            let body: Vec<String> = g.body.iter().map(print_literal).collect();
            let target = g
                .target
                .as_ref()
                .map(|t| format!(" {}", print_expr(t)))
                .unwrap_or_default();
            format!(
                "{} = {}{} : {{ {} }}",
                print_expr(&g.result),
                g.func.as_str(),
                target,
                body.join(", ")
            )
        }
    }
}

/// An expression with the fewest parentheses that keep its structure.
pub fn print_expr(e: &Expr) -> String {
    let mut out = String::new();
    write_expr(&mut out, e, 0);
    out
}

fn prec(op: BinOp) -> u8 {
    match op {
        BinOp::Add | BinOp::Sub => 1,
        BinOp::Mul | BinOp::Div | BinOp::Mod => 2,
        // Above a sign's 3... and 4 for the right-associative power; see `write_expr`.
        BinOp::Pow => 4,
    }
}

/// Writes `e`, parenthesised if its precedence is below `min`.
fn write_expr(out: &mut String, e: &Expr, min: u8) {
    match &e.kind {
        ExprKind::Var(v) => out.push_str(v),
        ExprKind::Wildcard => out.push('_'),
        ExprKind::Str(s) => out.push_str(&quote(s)),
        ExprKind::Int(i) => {
            if *i < 0 && min > 0 {
                let _ = write!(out, "({i})");
            } else {
                let _ = write!(out, "{i}");
            }
        }
        ExprKind::Float(f) => {
            let text = float_text(*f);
            if text.starts_with('-') && min > 0 {
                let _ = write!(out, "({text})");
            } else {
                out.push_str(&text);
            }
        }
        ExprKind::Quantity(q) => {
            let text = if q.value.fract() == 0.0 && q.value.abs() < 1e15 {
                format!("{:.0}", q.value)
            } else {
                float_text(q.value)
            };
            if text.starts_with('-') && min > 0 {
                let _ = write!(out, "({text} {})", q.unit);
            } else {
                let _ = write!(out, "{text} {}", q.unit);
            }
        }
        ExprKind::Neg(inner) => {
            let paren = min > 3;
            if paren {
                out.push('(');
            }
            out.push('-');
            match inner.kind {
                ExprKind::Var(_) | ExprKind::Wildcard | ExprKind::Call(..) | ExprKind::Neg(_) => {
                    write_expr(out, inner, 3)
                }
                _ => {
                    out.push('(');
                    write_expr(out, inner, 0);
                    out.push(')');
                }
            }
            if paren {
                out.push(')');
            }
        }
        ExprKind::Binary(op, l, r) => {
            let p = prec(*op);
            let paren = p < min;
            if paren {
                out.push('(');
            }
            // Left-associative operators group to the left, power to the right.
            let (left, right) = if *op == BinOp::Pow {
                (p + 1, p)
            } else {
                (p, p + 1)
            };
            write_expr(out, l, left);
            let _ = write!(out, " {} ", op.as_str());
            write_expr(out, r, right);
            if paren {
                out.push(')');
            }
        }
        ExprKind::Call(f, args) => {
            out.push_str(f.as_str());
            out.push('(');
            for (i, a) in args.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                write_expr(out, a, 0);
            }
            out.push(')');
        }
    }
}

/// A float as text that parses back to exactly the same value and always reads as a float.
pub fn float_text(f: f64) -> String {
    let s = format!("{f:?}");
    if s.contains(['.', 'e', 'E']) || !f.is_finite() {
        s
    } else {
        format!("{s}.0")
    }
}

/// A string constant, quoted and escaped.
pub fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
