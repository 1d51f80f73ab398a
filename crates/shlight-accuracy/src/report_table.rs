//! [`report_table`]: the accuracy suite's report as the plain-text table
//! `shlight accuracy` prints.

use std::fmt::Write as _;

use crate::suite::{self, Report};

/// A number in a short scientific form, or `-`.
fn sci(v: Option<f64>) -> String {
    v.map_or_else(|| "-".into(), |v| format!("{v:.2e}"))
}

/// The report as a plain-text table, one line per row (case, method,
/// resolution or samples, lmax, mean / max relative error, bound, slope,
/// pass), followed by the count of rows that pass and a legend of how the
/// errors and slopes are measured.
#[must_use]
pub fn report_table(report: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<13} {:<20} {:>10} {:>4} {:>9} {:>9} {:>9} {:>6}  pass",
        "case", "method", "res/N", "lmax", "mean", "max", "bound", "slope"
    );
    for r in &report.rows {
        let _ = writeln!(
            out,
            "{:<13} {:<20} {:>10} {:>4} {:>9} {:>9} {:>9} {:>6}  {}",
            r.case,
            r.method,
            r.setting(),
            r.lmax,
            sci(Some(r.mean_rel_err)),
            sci(Some(r.max_rel_err)),
            sci(r.bound),
            r.slope.map_or_else(|| "-".into(), |s| format!("{s:.2}")),
            if r.pass { "pass" } else { "FAIL" }
        );
    }
    let passed = report.rows.iter().filter(|r| r.pass).count();
    let _ = writeln!(
        out,
        "\n{passed} of {} rows pass. Errors are |E_est(n) - E_ref(n)| / max E over {} \
         Fibonacci normals:\ntruncation against the closed-form E; quadrature and mc-* \
         against the SH irradiance truncated at the same lmax.\nslope: fitted to the RMS \
         error against map width or samples (accepted: smooth / edges {:?} / {:?}, \
         mc uniform, importance {:?}, stratified, sobol {:?}).",
        report.rows.len(),
        suite::NORMALS,
        suite::SMOOTH_RATE,
        suite::EDGE_RATE,
        suite::IID_RATE,
        suite::QMC_RATE,
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::Row;

    fn row(case: &str, pass: bool) -> Row {
        Row {
            case: case.into(),
            method: "quadrature-equirect".into(),
            resolution: Some((64, 32)),
            samples: None,
            lmax: 2,
            mean_rel_err: 1.5e-4,
            max_rel_err: 3.25e-3,
            rms_rel_err: 2e-4,
            bound: None,
            slope: Some(-2.014),
            slope_range: Some(suite::SMOOTH_RATE),
            max_z: None,
            frac_z_over_3: None,
            pass,
        }
    }

    #[test]
    fn one_line_per_row_and_the_count_that_pass() {
        let report = Report {
            rows: vec![row("sphere", true), row("cap-10", false)],
            ..Report::default()
        };
        let table = report_table(&report);
        let lines: Vec<&str> = table.lines().collect();
        assert!(lines[0].starts_with("case") && lines[0].ends_with("pass"));
        assert_eq!(
            lines[1],
            "sphere        quadrature-equirect       64x32    2   1.50e-4   3.25e-3         -  -2.01  pass"
        );
        assert!(lines[2].starts_with("cap-10") && lines[2].ends_with("FAIL"));
        assert!(table.contains("\n1 of 2 rows pass."), "{table}");
        assert!(table.contains(&format!("over {} Fibonacci normals", suite::NORMALS)));
    }
}
