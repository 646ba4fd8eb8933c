//! The Python side of a RefAV program: statements (assignments, `output_scenario`, what is
//! refused), expressions, and calls bound to RefAV's signatures with their defaults.

use super::*;

impl Translator<'_> {
    pub(crate) fn stmt(&mut self, stmt: &Stmt) -> Res<()> {
        match stmt {
            Stmt::Assign(a) => {
                let [target] = a.targets.as_slice() else {
                    return Err(self.err(
                        "chained assignment",
                        "only `name = value` assignments are translated".into(),
                    ));
                };
                let Expr::Name(name) = target else {
                    return Err(self.err(
                        "assignment target",
                        format!(
                            "only assignments to a plain name are translated, not `{}`",
                            self.src(target)
                        ),
                    ));
                };
                let var = name.id.as_str().to_string();
                self.emit(format!(
                    "\n// line {}: {}",
                    self.line,
                    one_line(&self.src(stmt))
                ));
                match self.expr(&a.value, Some(&var)) {
                    Ok(v) => {
                        self.vars.insert(var, v);
                        Ok(())
                    }
                    Err(e) => {
                        self.vars.insert(var, Val::Poison);
                        Err(e)
                    }
                }
            }
            Stmt::Expr(e) => match e.value.as_ref() {
                Expr::Constant(_) => Ok(()), // a docstring or a bare literal does nothing
                Expr::Call(_) => {
                    self.expr(&e.value, None)?;
                    Ok(())
                }
                other => Err(self.err(
                    "expression statement",
                    format!("`{}` on its own does nothing RefAV defines", self.src(other)),
                )),
            },
            Stmt::Import(_) | Stmt::ImportFrom(_) => {
                self.notes
                    .push(format!("line {}: the import is ignored", self.line));
                Ok(())
            }
            Stmt::Pass(_) => Ok(()),
            other => Err(self.err(
                stmt_name(other),
                format!(
                    "a {} cannot be translated: only assignments and calls of RefAV's functions are",
                    stmt_name(other)
                ),
            )),
        }
    }

    pub(crate) fn expr(&mut self, e: &Expr, hint: Option<&str>) -> Res<Val> {
        match e {
            Expr::Name(n) => {
                let id = n.id.as_str();
                if let Some(v) = self.vars.get(id) {
                    if let Val::Poison = v {
                        return Err(self.err(POISON, String::new()));
                    }
                    return Ok(v.clone());
                }
                match id {
                    "log_dir" => Ok(Val::LogDir),
                    "output_dir" => Ok(Val::OutputDir),
                    _ => {
                        if let Some(sig) = signatures::lookup(id) {
                            Ok(Val::Func(sig))
                        } else {
                            Err(self.broken(
                                "name",
                                format!("name '{id}' is not defined before line {}", self.line),
                            ))
                        }
                    }
                }
            }
            Expr::Constant(c) => {
                match &c.value {
                    Constant::Str(s) => Ok(Val::Str(s.clone())),
                    Constant::Int(i) => i.to_string().parse::<f64>().map(Val::Num).map_err(|_| {
                        self.err("integer", format!("the integer {i} is out of range"))
                    }),
                    Constant::Float(f) => Ok(Val::Num(*f)),
                    Constant::Bool(b) => Ok(Val::Bool(*b)),
                    Constant::None => Ok(Val::None),
                    _ => Err(self.err(
                        "constant",
                        format!("the constant `{}` has no RefAV meaning", self.src(e)),
                    )),
                }
            }
            Expr::UnaryOp(u) if matches!(u.op, ast::UnaryOp::USub) => {
                match self.expr(&u.operand, None)? {
                    Val::Num(x) => Ok(Val::Num(-x)),
                    v => Err(self.err(
                        "unary minus",
                        format!("cannot negate {} in `{}`", v.kind_name(), self.src(e)),
                    )),
                }
            }
            Expr::Attribute(a) => {
                if let Expr::Name(m) = a.value.as_ref() {
                    if matches!(m.id.as_str(), "np" | "numpy" | "math") && a.attr.as_str() == "inf"
                    {
                        return Ok(Val::Num(f64::INFINITY));
                    }
                }
                Err(self.err(
                    "attribute",
                    format!("`{}` is not translated (only np.inf is)", self.src(e)),
                ))
            }
            Expr::List(l) => {
                let mut items = Vec::new();
                for x in &l.elts {
                    items.push(self.expr(x, None)?);
                }
                Ok(Val::List(items))
            }
            Expr::Tuple(l) => {
                let mut items = Vec::new();
                for x in &l.elts {
                    items.push(self.expr(x, None)?);
                }
                Ok(Val::List(items))
            }
            Expr::Call(c) => self.call(c, hint),
            other => Err(self.err(
                expr_name(other),
                format!(
                    "a {} (`{}`) cannot be translated",
                    expr_name(other),
                    self.src(other)
                ),
            )),
        }
    }

    pub(crate) fn call(&mut self, c: &ast::ExprCall, hint: Option<&str>) -> Res<Val> {
        // `float('inf')`
        if let Expr::Name(n) = c.func.as_ref() {
            if n.id.as_str() == "float" {
                if let [Expr::Constant(k)] = c.args.as_slice() {
                    if let Constant::Str(s) = &k.value {
                        match s.trim().to_ascii_lowercase().as_str() {
                            "inf" | "+inf" | "infinity" => return Ok(Val::Num(f64::INFINITY)),
                            "-inf" | "-infinity" => return Ok(Val::Num(f64::NEG_INFINITY)),
                            _ => {}
                        }
                    }
                }
            }
        }
        let callee = match c.func.as_ref() {
            Expr::Name(n) => {
                let id = n.id.as_str();
                if let Some((_, why)) = signatures::UNSUPPORTED.iter().find(|u| u.0 == id) {
                    return Err(self.err(
                        id,
                        format!("RefAV's {id}() {why}, which Scenalog does not have"),
                    ));
                }
                match self.vars.get(id) {
                    Some(Val::Poison) => return Err(self.err(POISON, String::new())),
                    Some(v) => v.clone(),
                    None => match signatures::lookup(id) {
                        Some(sig) => Val::Func(sig),
                        None => {
                            return Err(
                                self.broken(id, format!("RefAV has no function named '{id}'"))
                            )
                        }
                    },
                }
            }
            Expr::Call(_) => self.expr(&c.func, None)?,
            other => {
                return Err(self.err(
                    "call",
                    format!(
                        "only RefAV's functions can be called, not `{}`",
                        self.src(other)
                    ),
                ))
            }
        };
        if let (Val::Func(sig), [Expr::Lambda(l)]) = (&callee, c.args.as_slice()) {
            let takes_log_dir = l.args.args.iter().any(|a| a.def.arg.as_str() == "log_dir");
            if sig.name == "scenario_not" && !takes_log_dir {
                return Err(self.broken(
                    "scenario_not",
                    "ValueError: the function scenario_not wraps (a lambda) does not have 'log_dir' as a parameter".into(),
                ));
            }
        }
        let mut pos = Vec::new();
        for a in &c.args {
            if let Expr::Starred(_) = a {
                return Err(self.err("*args", "star arguments are not translated".into()));
            }
            pos.push(self.expr(a, None)?);
        }
        let mut kw = Vec::new();
        for k in &c.keywords {
            let Some(name) = &k.arg else {
                return Err(self.err("**kwargs", "`**` arguments are not translated".into()));
            };
            kw.push((name.as_str().to_string(), self.expr(&k.value, None)?));
        }
        match callee {
            Val::Func(sig) => {
                let args = self.bind(sig, pos, kw)?;
                self.apply(sig, args, hint)
            }
            Val::Wrapped(wrapper, sig) => self.apply_wrapped(wrapper, sig, pos, kw, hint),
            Val::NotReversed(sig) => self.apply_not_reversed(sig, pos, kw, hint),
            v => Err(self.broken(
                "call",
                format!("{} is not callable ({})", v.kind_name(), self.src(c)),
            )),
        }
    }

    /// Binds arguments to parameters as Python does; what Python rejects is an error here.
    pub(crate) fn bind(
        &mut self,
        sig: &'static Signature,
        pos: Vec<Val>,
        mut kw: Vec<(String, Val)>,
    ) -> Res<BTreeMap<&'static str, Val>> {
        let mut out: BTreeMap<&'static str, Val> = BTreeMap::new();
        // RefAV's first API: `accelerating(track_candidates, log_dir, thresh=0)`, which its
        // later code mapped to `min_accel=thresh, max_accel=inf` (no stationary exclusion).
        let legacy = if sig.name == signatures::FIRST_API_FUNCTION {
            kw.iter()
                .position(|(k, _)| k == signatures::FIRST_API_KEYWORD)
                .map(|i| kw.remove(i).1)
        } else {
            None
        };
        if let Some(thresh) = legacy {
            let x = self.num(sig.name, signatures::FIRST_API_KEYWORD, &thresh)?;
            self.first_api = true;
            self.notes.push(format!(
                "line {}: accelerating(..., thresh={}) is RefAV's first API: forward acceleration >= {} m/s², no upper bound, stationary objects not excluded (the current API rejects the keyword)",
                self.line,
                fmt_num(x),
                fmt_num(x)
            ));
            out.insert(signatures::FIRST_API_KEYWORD, Val::Num(x));
        }
        if pos.len() > sig.params.len() {
            return Err(self.broken(
                sig.name,
                format!(
                    "TypeError: {}() takes {} positional arguments but {} were given",
                    sig.name,
                    sig.params.len(),
                    pos.len()
                ),
            ));
        }
        for (p, v) in sig.params.iter().zip(pos) {
            out.insert(p.0, v);
        }
        for (k, v) in kw {
            match sig.params.iter().find(|p| p.0 == k) {
                Some(p) => {
                    if out.insert(p.0, v).is_some() {
                        return Err(self.broken(
                            sig.name,
                            format!(
                                "TypeError: {}() got multiple values for argument '{k}'",
                                sig.name
                            ),
                        ));
                    }
                }
                None if sig.var_kwargs => {}
                None => {
                    return Err(self.broken(
                        sig.name,
                        format!(
                            "TypeError: {}() got an unexpected keyword argument '{k}'",
                            sig.name
                        ),
                    ))
                }
            }
        }
        for (name, d) in sig.params {
            if out.contains_key(name) {
                continue;
            }
            let v = match d {
                Default::Required => {
                    return Err(self.broken(
                        sig.name,
                        format!(
                            "TypeError: {}() missing required argument '{name}'",
                            sig.name
                        ),
                    ))
                }
                Default::Num(x) => Val::Num(*x),
                Default::Str(s) => Val::Str((*s).to_string()),
                Default::None => Val::None,
                Default::Bool(b) => Val::Bool(*b),
            };
            out.insert(name, v);
        }
        Ok(out)
    }
}

pub(crate) fn stmt_name(s: &Stmt) -> &'static str {
    match s {
        Stmt::FunctionDef(_) | Stmt::AsyncFunctionDef(_) => "function definition",
        Stmt::ClassDef(_) => "class definition",
        Stmt::Return(_) => "return statement",
        Stmt::Delete(_) => "del statement",
        Stmt::AugAssign(_) => "augmented assignment",
        Stmt::AnnAssign(_) => "annotated assignment",
        Stmt::For(_) | Stmt::AsyncFor(_) => "for loop",
        Stmt::While(_) => "while loop",
        Stmt::If(_) => "if statement",
        Stmt::With(_) | Stmt::AsyncWith(_) => "with statement",
        Stmt::Match(_) => "match statement",
        Stmt::Raise(_) => "raise statement",
        Stmt::Try(_) | Stmt::TryStar(_) => "try statement",
        Stmt::Assert(_) => "assert statement",
        Stmt::Global(_) | Stmt::Nonlocal(_) => "global declaration",
        _ => "statement",
    }
}

pub(crate) fn expr_name(e: &Expr) -> &'static str {
    match e {
        Expr::BoolOp(_) => "boolean operator",
        Expr::NamedExpr(_) => "walrus assignment",
        Expr::BinOp(_) => "arithmetic expression",
        Expr::UnaryOp(_) => "unary operator",
        Expr::Lambda(_) => "lambda",
        Expr::IfExp(_) => "conditional expression",
        Expr::Dict(_) => "dict literal",
        Expr::Set(_) => "set literal",
        Expr::ListComp(_) | Expr::SetComp(_) | Expr::DictComp(_) | Expr::GeneratorExp(_) => {
            "comprehension"
        }
        Expr::Compare(_) => "comparison",
        Expr::Subscript(_) => "subscript",
        Expr::JoinedStr(_) | Expr::FormattedValue(_) => "f-string",
        Expr::Starred(_) => "starred expression",
        Expr::Slice(_) => "slice",
        _ => "expression",
    }
}
