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
