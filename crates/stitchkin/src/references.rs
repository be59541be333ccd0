//! The published works the presets, the thread model and the stitch process
//! rest on (docs/references.md), as a reader sees them cited: by authors and
//! year. Code comments cite them as "seed 000" … "seed 004", and a model
//! file's `seed` field names one by its number; everything printed for
//! people cites them through this table, so the wording is one.

/// One published work: its number among the seeds and its short citation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reference {
    /// The seed's number as a model file's `seed` field writes it: `"000"`.
    pub seed: &'static str,
    /// Authors and year: `Manoilenko et al. (2024)`; a work that states no
    /// year has `n.d.`.
    pub citation: &'static str,
}

/// Every seed, in order (docs/references.md, "The seeds").
pub const ALL: [Reference; 5] = [
    Reference {
        seed: "000",
        citation: "Manoilenko et al. (2024)",
    },
    Reference {
        seed: "001",
        citation: "Dvorzhak et al. (n.d.)",
    },
    Reference {
        seed: "002",
        citation: "Kharzhevskyi et al. (n.d.)",
    },
    Reference {
        seed: "003",
        citation: "Dvorzhak et al. (2024)",
    },
    Reference {
        seed: "004",
        citation: "Polyakov (2022)",
    },
];

/// The short citation of seed `n` (0…4): `cite(4)` is `Polyakov (2022)`.
/// A number that is not a seed's gets "an unlisted work".
pub fn cite(n: usize) -> &'static str {
    ALL.get(n).map_or("an unlisted work", |r| r.citation)
}

/// The short citation of a model file's `seed` field (`"000"`, `"4"`), or
/// `None` for one that names no seed.
pub fn cite_seed(seed: &str) -> Option<&'static str> {
    let n: usize = seed.trim().parse().ok()?;
    ALL.get(n).map(|r| r.citation)
}

/// `text` with every "seed NNN" (or "Seed NNN") of a listed seed written as
/// its citation: for free text from model files (caveats, a parameter's
/// source) and anything else printed for people. "seed 000's figures"
/// becomes "Manoilenko et al. (2024)'s figures"; other words are kept.
pub fn cited(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.contains("eed 00") {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 32);
    let mut rest = text;
    while let Some(at) = rest.find("eed 00") {
        // "seed " or "Seed " at a word's start, then three digits.
        let start = at.saturating_sub(1);
        let head = &rest[start..];
        let word_start = start == 0 || !rest[..start].chars().next_back().is_some_and(char::is_alphanumeric);
        let digits = head.get(5..8);
        let after = head.get(8..9).and_then(|s| s.chars().next());
        let r = digits.and_then(|d| ALL.iter().find(|r| r.seed == d));
        match r {
            Some(r)
                if at >= 1
                    && (head.starts_with("seed ") || head.starts_with("Seed "))
                    && word_start
                    && !after.is_some_and(|c| c.is_ascii_digit()) =>
            {
                out.push_str(&rest[..start]);
                out.push_str(r.citation);
                rest = &rest[start + 8..];
            }
            _ => {
                out.push_str(&rest[..at + 6]);
                rest = &rest[at + 6..];
            }
        }
    }
    out.push_str(rest);
    std::borrow::Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_seed_has_authors_and_a_year() {
        for (n, r) in ALL.iter().enumerate() {
            assert_eq!(r.seed, format!("{n:03}"));
            assert!(r.citation.ends_with(')') && r.citation.contains(" ("), "{r:?}");
        }
        assert_eq!(cite(0), "Manoilenko et al. (2024)");
        assert_eq!(cite(4), "Polyakov (2022)");
        assert_eq!(cite_seed("004"), Some("Polyakov (2022)"));
        assert_eq!(cite_seed("2"), Some("Kharzhevskyi et al. (n.d.)"));
        assert_eq!(cite_seed("x"), None);
        assert_eq!(cite_seed("007"), None);
    }

    #[test]
    fn free_text_cites_by_authors_and_year() {
        assert_eq!(
            cited("seed 000 Table 1: r1 = 4 (seed 004 §2.3)"),
            "Manoilenko et al. (2024) Table 1: r1 = 4 (Polyakov (2022) §2.3)"
        );
        assert_eq!(
            cited("Seed 001's allowance; seed 000's figures"),
            "Dvorzhak et al. (n.d.)'s allowance; Manoilenko et al. (2024)'s figures"
        );
        // Not a seed's citation: another number, a longer word, a longer number.
        for kept in ["reseed 000", "seed 0001", "seed 009", "seed 00", "seed 1"] {
            assert_eq!(cited(kept), kept);
        }
        assert_eq!(cited("no citation here"), "no citation here");
    }
}
