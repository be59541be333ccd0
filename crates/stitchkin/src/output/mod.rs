//! Writing results: CSV and JSON, SVG plots, and files that are never
//! half-written nor destroy what they point at ([`write_atomic`], [`Sink`]).

pub mod drawing;
mod file;
pub mod plots;
pub mod report;
pub mod svg;
pub mod text;

use std::io::Write;

use rayon::prelude::*;
use serde::Serialize;

use crate::eval::CycleTable;
use crate::eval::stitch_process::StitchSummary;
use crate::format::{fmt_num, push_num};
use crate::model::{Model, Params};

pub use file::{Sink, check_folder, remove_temporaries, write_atomic};

/// The table as CSV: a header of unit-carrying column names, one row per φ.
pub fn write_csv(table: &CycleTable, out: &mut impl Write) -> std::io::Result<()> {
    let names: Vec<&str> = table.columns.iter().map(|c| c.name.as_str()).collect();
    writeln!(out, "{}", names.join(","))?;
    // Rows are written as text a block at a time on every core, and the
    // blocks go out in order while the next batch is being written as text;
    // two batches of blocks are all that is held.
    const BLOCK_ROWS: usize = 1024;
    let rows = table.rows();
    let batch_rows = BLOCK_ROWS * 2 * rayon::current_num_threads();
    let text = |batch: usize| -> Vec<Vec<u8>> {
        let starts: Vec<usize> = (batch..rows.min(batch + batch_rows)).step_by(BLOCK_ROWS).collect();
        starts
            .into_par_iter()
            .map(|start| csv_rows(table, start..rows.min(start + BLOCK_ROWS)))
            .collect()
    };
    let write = |blocks: Vec<Vec<u8>>, out: &mut dyn Write| blocks.iter().try_for_each(|b| out.write_all(b));
    let mut pending: Vec<Vec<u8>> = Vec::new();
    for batch in (0..rows).step_by(batch_rows) {
        let mut next = Vec::new();
        rayon::in_place_scope(|s| {
            s.spawn(|_| next = text(batch));
            write(std::mem::take(&mut pending), &mut *out)
        })?;
        pending = next;
    }
    write(pending, out)
}

/// The CSV text of the table's `rows`.
fn csv_rows(table: &CycleTable, rows: std::ops::Range<usize>) -> Vec<u8> {
    // Room for each number's usual length, so the text is not moved as it grows.
    let mut text = Vec::with_capacity(rows.len() * table.columns.len() * 16);
    // The values are read a few rows at a time, column by column, into rows
    // on the stack: a row read across a hundred columns would wait for
    // memory at every column.
    const FEW: usize = 32;
    let ncol = table.columns.len();
    if ncol == 0 {
        return vec![b'\n'; rows.len()];
    }
    let mut few = vec![0.0; FEW * ncol];
    for start in rows.clone().step_by(FEW) {
        let end = rows.end.min(start + FEW);
        for (k, c) in table.columns.iter().enumerate() {
            for (i, v) in c.values[start..end].iter().enumerate() {
                few[i * ncol + k] = *v;
            }
        }
        for row in few.chunks_exact(ncol).take(end - start) {
            for (k, v) in row.iter().enumerate() {
                if k > 0 {
                    text.push(b',');
                }
                push_num(&mut text, *v);
            }
            text.push(b'\n');
        }
    }
    text
}

#[derive(Serialize)]
struct JsonParam<'a> {
    name: &'a str,
    value: f64,
    unit: &'a str,
    derived: bool,
}

#[derive(Serialize)]
struct JsonRun<'a> {
    model: &'a str,
    title: Option<&'a str>,
    seed: Option<&'a str>,
    phi_start_deg: f64,
    parameters: Vec<JsonParam<'a>>,
    #[serde(flatten)]
    table: &'a CycleTable,
}

/// A match's result as JSON, the same from every front end: the stitch
/// summary with the model's name, its caveats (papers cited by authors and
/// year) and each cam and follower's checks (`cams`).
pub fn match_json(model: &Model, table: &CycleTable, stitch: &StitchSummary) -> serde_json::Result<serde_json::Value> {
    let mut json = serde_json::to_value(stitch)?;
    json["model"] = serde_json::json!(model.name());
    let caveats: Vec<String> = model
        .caveats()
        .iter()
        .map(|c| crate::references::cited(c).into_owned())
        .collect();
    json["caveats"] = serde_json::json!(caveats);
    json["cams"] = serde_json::to_value(&table.cams)?;
    Ok(json)
}

/// The run as JSON: model, parameter values, columns and summaries.
pub fn write_json(model: &Model, params: &Params, table: &CycleTable, out: &mut impl Write) -> std::io::Result<()> {
    let parameters = model
        .params
        .iter()
        .zip(&params.values)
        .filter(|(p, _)| !p.is_derived())
        .map(|(p, v)| JsonParam {
            name: &p.name,
            value: *v,
            unit: p.unit_str(),
            derived: false,
        })
        .collect();
    let run = JsonRun {
        model: model.name(),
        title: model.title(),
        seed: model.seed(),
        phi_start_deg: model.phi_start_deg(),
        parameters,
        table,
    };
    serde_json::to_writer_pretty(&mut *out, &run).map_err(std::io::Error::other)?;
    writeln!(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_exact_enough() {
        assert_eq!(fmt_num(175.0), "175");
        assert_eq!(fmt_num(0.1 + 0.2), "0.3");
        assert_eq!(fmt_num(-1.5e-10), "-1.5e-10");
        assert_eq!(fmt_num(9.18e-16), "9.18e-16");
        assert_eq!(fmt_num(0.000123), "0.000123");
        assert_eq!(fmt_num(std::f64::consts::PI), "3.14159265359");
    }
}
