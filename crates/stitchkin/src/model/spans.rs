//! Where things are in a model file's text, for error messages.

use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// A place in the model, e.g. `groups[2].lengths[1]`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct KeyPath(Vec<Seg>);

#[derive(Debug, Clone, PartialEq, Eq)]
enum Seg {
    Key(String),
    Index(usize),
}

impl KeyPath {
    pub fn root() -> Self {
        KeyPath(Vec::new())
    }
    pub fn key(&self, k: &str) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Key(k.to_string()));
        p
    }
    pub fn index(&self, i: usize) -> Self {
        let mut p = self.clone();
        p.0.push(Seg::Index(i));
        p
    }

    /// Whether the field at this place names its unit (`m_mm`,
    /// `phase_deg`, `force_n[0]`, `rate_n_per_mm`): its last key, past any
    /// index, ends in `_mm`, `_deg` or `_n`. The keys of tables keyed by
    /// the model's own names (`[points]`, a group's `unknowns`) are names,
    /// not fields.
    pub fn names_its_unit(&self) -> bool {
        let keys: Vec<&str> = self
            .0
            .iter()
            .filter_map(|s| match s {
                Seg::Key(k) => Some(k.as_str()),
                Seg::Index(_) => None,
            })
            .collect();
        let Some(last) = keys.last() else { return false };
        let keyed_by_name = match keys.len() {
            n if n >= 2 => keys[n - 2] == "points" || keys[n - 2] == "unknowns",
            _ => false,
        };
        !keyed_by_name && ["_mm", "_deg", "_n"].iter().any(|u| last.ends_with(u))
    }
}

impl std::fmt::Display for KeyPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, s) in self.0.iter().enumerate() {
            match s {
                Seg::Key(k) if i == 0 => write!(f, "{k}")?,
                Seg::Key(k) => write!(f, ".{k}")?,
                Seg::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// The file parsed once more into a span-carrying tree.
pub struct SpanIndex<'a> {
    root: Option<Spanned<DeTable<'a>>>,
}

impl<'a> SpanIndex<'a> {
    pub fn new(text: &'a str) -> Self {
        SpanIndex {
            root: DeTable::parse(text).ok(),
        }
    }

    /// Span of the deepest part of `path` found in the file (a missing key
    /// points at its table).
    pub fn find(&self, path: &KeyPath) -> Option<std::ops::Range<usize>> {
        let root = self.root.as_ref()?;
        let mut span = None;
        let mut table: Option<&DeTable<'_>> = Some(root.get_ref());
        let mut value: Option<&DeValue<'_>> = None;
        for seg in &path.0 {
            match seg {
                Seg::Key(k) => {
                    let t = match (table, value) {
                        (Some(t), _) => t,
                        (None, Some(DeValue::Table(t))) => t,
                        _ => break,
                    };
                    let Some((key, v)) = t.iter().find(|(key, _)| key.get_ref().as_ref() == k.as_str()) else {
                        break;
                    };
                    span = Some(if matches!(v.get_ref(), DeValue::Table(_)) {
                        key.span()
                    } else {
                        v.span()
                    });
                    table = None;
                    value = Some(v.get_ref());
                }
                Seg::Index(i) => {
                    let Some(DeValue::Array(a)) = value else { break };
                    let Some(v) = a.get(*i) else { break };
                    span = Some(v.span());
                    value = Some(v.get_ref());
                }
            }
        }
        span
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_nested_values() {
        let text = "[model]\nname = \"x\"\n\n[[groups]]\ntype = \"rrr\"\nlengths = [1, \"l_ab\"]\n";
        let idx = SpanIndex::new(text);
        let p = KeyPath::root().key("groups").index(0).key("lengths").index(1);
        assert_eq!(p.to_string(), "groups[0].lengths[1]");
        let s = idx.find(&p).unwrap();
        assert_eq!(&text[s], "\"l_ab\"");
        let s = idx.find(&KeyPath::root().key("model").key("name")).unwrap();
        assert_eq!(&text[s], "\"x\"");
        // A missing key falls back to the deepest part found.
        let s = idx.find(&KeyPath::root().key("groups").index(0).key("nope")).unwrap();
        assert!(
            text[s.clone()].contains("rrr") || text[s.clone()].contains("[[groups]]"),
            "{:?}",
            &text[s]
        );
    }
}
