//! Aligned columns under a header, for the tables of the studies.

/// Columns under a header, widths in characters, two spaces apart: the
/// first left-aligned when `names_first` (parameter names), the others
/// right-aligned. Every row has as many cells as the header.
pub fn table(header: &[String], rows: &[Vec<String>], names_first: bool) -> String {
    let width = |c: usize| {
        rows.iter()
            .map(|r| r[c].chars().count())
            .chain([header[c].chars().count()])
            .max()
            .unwrap_or(0)
    };
    let widths: Vec<usize> = (0..header.len()).map(width).collect();
    let line = |cells: &[String]| {
        let s: Vec<String> = cells
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(i, (c, w))| {
                let pad = " ".repeat(w - c.chars().count());
                if i == 0 && names_first {
                    format!("{c}{pad}")
                } else {
                    format!("{pad}{c}")
                }
            })
            .collect();
        s.join("  ").trim_end().to_string() + "\n"
    };
    let mut out = line(header);
    for r in rows {
        out += &line(r);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_align_by_characters() {
        let head = ["name".to_string(), "μ, deg".to_string()];
        let rows = vec![vec!["a".to_string(), "1.5".to_string()], vec!["long".into(), "".into()]];
        assert_eq!(table(&head, &rows, true), "name  μ, deg\na        1.5\nlong\n");
        assert_eq!(table(&head, &rows, false), "name  μ, deg\n   a     1.5\nlong\n");
    }
}
