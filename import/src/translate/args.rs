//! Reading a RefAV function's bound arguments: scenarios, numbers, words from the catalog's
//! lists, and `log_dir`.

use super::*;

impl Translator<'_> {
    pub(crate) fn scen(&self, f: &str, param: &str, v: &Val) -> Res<Scen> {
        match v {
            Val::Scen(s) => Ok(s.clone()),
            other => Err(self.broken(
                f,
                format!(
                    "{f}()'s argument '{param}' must be a scenario, got {}",
                    other.kind_name()
                ),
            )),
        }
    }

    pub(crate) fn num(&self, f: &str, param: &str, v: &Val) -> Res<f64> {
        match v {
            Val::Num(x) if !x.is_nan() => Ok(*x),
            Val::Bool(b) => Ok(if *b { 1.0 } else { 0.0 }),
            other => Err(self.broken(
                f,
                format!(
                    "{f}()'s argument '{param}' must be a number, got {}",
                    other.kind_name()
                ),
            )),
        }
    }

    /// A string argument that must be one of `allowed` (None allowed when `none_ok`).
    pub(crate) fn word(
        &self,
        f: &str,
        param: &str,
        v: &Val,
        allowed: &[&str],
        none_ok: bool,
    ) -> Res<Option<String>> {
        match v {
            Val::None if none_ok => Ok(None),
            Val::Str(s) if allowed.is_empty() || allowed.contains(&s.as_str()) => {
                if s.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == ' ')
                {
                    Ok(Some(s.clone()))
                } else {
                    Err(self.err(f, format!("{f}(): '{s}' is not a value Scenalog knows")))
                }
            }
            other => Err(self.err(
                f,
                format!(
                    "{f}()'s argument '{param}' is {}; it must be one of {}{}",
                    match other {
                        Val::Str(s) => format!("'{s}'"),
                        o => o.kind_name().to_string(),
                    },
                    allowed
                        .iter()
                        .map(|a| format!("'{a}'"))
                        .collect::<Vec<_>>()
                        .join(", "),
                    if none_ok { " or None" } else { "" }
                ),
            )),
        }
    }

    pub(crate) fn log_dir(&self, f: &str, args: &BTreeMap<&'static str, Val>) -> Res<()> {
        match args.get("log_dir") {
            Some(Val::LogDir) | None => Ok(()),
            Some(v) => Err(self.broken(
                f,
                format!(
                    "{f}()'s argument 'log_dir' must be log_dir, got {}",
                    v.kind_name()
                ),
            )),
        }
    }
}
