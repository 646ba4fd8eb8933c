//! The relations a program can use (`scenalog catalog [NAME]`): the catalog (every relation a
//! log provides: name, typed columns, closed string domains, a one-line doc) and the prelude's
//! concepts (relations written once in Scenalog), all of them or one by name, as text or JSON.

use scenalog_facts::catalog::{self, RelationSpec};
use scenalog_rules::prelude::{self, PreludeRelation};

use crate::api::error::Error;

/// What `scenalog catalog` shows.
pub enum Catalog {
    /// Every catalog relation, then the prelude's concepts.
    All,
    /// One relation of the catalog.
    Relation(&'static RelationSpec),
    /// One concept of the prelude.
    Concept(&'static PreludeRelation),
}

/// The whole catalog and prelude (`name` `None`), or the relation or concept of that name (the
/// prelude's first); an unknown name is an error listing the names there are.
pub fn catalog(name: Option<&str>) -> Result<Catalog, Error> {
    let Some(name) = name else {
        return Ok(Catalog::All);
    };
    if let Some(p) = prelude::relation(name) {
        return Ok(Catalog::Concept(p));
    }
    if let Some(r) = catalog::relation(name) {
        return Ok(Catalog::Relation(r));
    }
    let names: Vec<&str> = catalog::catalog()
        .iter()
        .map(|r| r.name)
        .chain(prelude::relations().iter().map(|r| r.name.as_str()))
        .collect();
    Err(Error::plain(format!(
        "no relation `{name}` in the catalog or the prelude; they have: {}",
        names.join(", ")
    )))
}

impl Catalog {
    /// As JSON: an array of relation objects (the catalog's, then the prelude's), or one.
    pub fn json(&self) -> serde_json::Value {
        match self {
            Catalog::All => {
                let mut all: Vec<serde_json::Value> =
                    catalog::catalog().iter().map(|r| r.to_json()).collect();
                all.extend(prelude::relations().iter().map(|r| r.to_json()));
                serde_json::Value::Array(all)
            }
            Catalog::Relation(r) => r.to_json(),
            Catalog::Concept(p) => p.to_json(),
        }
    }

    /// As text: the catalog's relations and the prelude's concepts, or one with its columns
    /// (their types and closed domains) or its definition.
    pub fn text(&self) -> String {
        match self {
            Catalog::All => format!(
                "{}\nConcepts (the prelude: relations every program can use without defining \
                 them)\n{}",
                catalog::render_text(),
                prelude::render_text()
            ),
            Catalog::Concept(p) => {
                let mut out = format!("{} (prelude)\n    {}\n", p.signature(), p.doc);
                for line in &p.definition {
                    out.push_str(&format!("    {line}\n"));
                }
                out
            }
            Catalog::Relation(r) => {
                let mut out = format!("{r}\n    {}\n", r.doc);
                for c in r.columns {
                    let values = if c.values.is_empty() {
                        String::new()
                    } else {
                        let v: Vec<String> = c.values.iter().map(|v| format!("{v:?}")).collect();
                        format!(", one of {}", v.join(", "))
                    };
                    out.push_str(&format!("    {}: {}{values}\n", c.name, c.ty));
                }
                out
            }
        }
    }
}
