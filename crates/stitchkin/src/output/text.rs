//! Results as text: curves as one-line sparklines for a terminal, and one
//! module per study for its tables and CSV.

pub mod cam;
pub mod nomogram;

pub mod cam_summary;
pub mod columns;
pub mod compare_2d3d;
pub mod consumption;
pub mod cycle;
pub mod fit;
pub mod fit_measured;
pub mod follower_cam;
pub mod matching;
pub mod readings;
pub mod sensitivity;
pub mod straightness;
pub mod stroke;
pub mod sweep;
pub mod tune;

/// The eight heights of a sparkline, lowest first.
/// The widest a name column grows: a longer name runs past the column
/// instead of pushing every row across the screen (and past what a format
/// width can hold).
pub(crate) const MAX_NAME_WIDTH: usize = 40;

/// The width of a column of names of lengths `lens`: the longest, at least
/// `min`, at most [`MAX_NAME_WIDTH`].
pub(crate) fn name_width(lens: impl IntoIterator<Item = usize>, min: usize) -> usize {
    lens.into_iter()
        .max()
        .unwrap_or(0)
        .max(min)
        .min(MAX_NAME_WIDTH.max(min))
}

const BARS: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];

/// `values` as a line of `cols` block characters, each the mean of its share
/// of the values, from `lo` (▁) to `hi` (█); a value outside [lo, hi] takes
/// the nearest end. An empty curve or `cols` = 0 gives an empty line.
pub fn sparkline(values: &[f64], lo: f64, hi: f64, cols: usize) -> String {
    let n = values.len();
    if n == 0 || cols == 0 {
        return String::new();
    }
    let span = hi - lo;
    (0..cols)
        .map(|c| {
            let (a, b) = (c * n / cols, ((c + 1) * n / cols).max(c * n / cols + 1).min(n));
            let mean = values[a..b].iter().sum::<f64>() / (b - a) as f64;
            let level = if span > 0.0 && mean.is_finite() {
                ((mean - lo) / span * 7.0).round().clamp(0.0, 7.0) as usize
            } else {
                0
            };
            BARS[level]
        })
        .collect()
}

/// Which of `cols` equal parts of one turn starting at `start_deg` lie
/// (at their middle) inside the φ window [from, to] (deg, `to` may pass
/// 360): a marker line for a sparkline over that turn.
pub fn window_marks(start_deg: f64, cols: usize, window: [f64; 2], mark: char) -> String {
    let len = (window[1] - window[0]).rem_euclid(360.0);
    (0..cols)
        .map(|c| {
            let phi = start_deg + (c as f64 + 0.5) * 360.0 / cols as f64;
            if (phi - window[0]).rem_euclid(360.0) <= len {
                mark
            } else {
                ' '
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparkline_heights_and_means() {
        assert_eq!(
            sparkline(&[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0], 0.0, 7.0, 8),
            "▁▂▃▄▅▆▇█"
        );
        // Two values a column: their mean; out of range clamps.
        assert_eq!(sparkline(&[0.0, 2.0, 7.0, 7.0, -5.0, 50.0], 0.0, 7.0, 3), "▂██");
        assert_eq!(sparkline(&[], 0.0, 1.0, 5), "");
        assert_eq!(sparkline(&[3.0; 4], 3.0, 3.0, 2), "▁▁");
        // More columns than values: each value fills its own columns.
        assert_eq!(sparkline(&[0.0, 7.0], 0.0, 7.0, 4), "▁▁██");
    }

    #[test]
    fn window_marks_wrap() {
        assert_eq!(window_marks(0.0, 12, [300.0, 360.0], '~'), "          ~~");
        assert_eq!(window_marks(0.0, 12, [330.0, 390.0], '~'), "~          ~");
        assert_eq!(window_marks(180.0, 4, [270.0, 360.0], '~'), " ~  ");
    }
}
