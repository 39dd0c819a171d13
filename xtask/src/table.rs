//! The results as text tables: aligned columns for the terminal, pipes for report.md.

use crate::results::ResultRow;

/// Column headers of the per-scene tables.
pub const HEADERS: [&str; 11] = [
    "configuration",
    "ms/step",
    "steps/s",
    "max pen mm",
    "mean pen mm",
    "drift mm",
    "jitter mm/s",
    "energy %",
    "rest s",
    "NaN",
    "check",
];

fn mm(meters: f64) -> String {
    format!("{:.2}", meters * 1e3)
}

/// The cells of one row, in `HEADERS` order.
pub fn cells(row: &ResultRow) -> Vec<String> {
    let m = &row.outcome.metrics;
    let config = if row.verdict_run {
        format!("{} [verdict, full length]", row.config)
    } else {
        row.config.to_string()
    };
    let check = match (&row.outcome.error, &row.check) {
        (Some(e), _) => format!("ERROR: {e}"),
        (None, Some(c)) => format!(
            "{} {} {:.4}/{}",
            if c.passed { "pass" } else { "FAIL" },
            c.check,
            c.measured,
            c.limit
        ),
        (None, None) => "-".into(),
    };
    vec![
        config,
        format!("{:.3}", row.outcome.timing.median_ms),
        format!("{:.0}", row.steps_per_second()),
        mm(f64::from(m.max_penetration)),
        mm(m.mean_penetration),
        mm(f64::from(m.max_drift)),
        m.jitter_rms.map_or("-".into(), mm),
        m.energy_drift
            .map_or("-".into(), |e| format!("{:+.2}", e * 100.0)),
        m.time_to_rest.map_or("never".into(), |t| format!("{t:.2}")),
        m.nan_bodies.to_string(),
        check,
    ]
}

/// Space-aligned table: the first column left-aligned, numbers right-aligned, the check
/// column left-aligned.
pub fn aligned(rows: &[Vec<String>]) -> String {
    let mut widths: Vec<usize> = HEADERS.iter().map(|h| h.len()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let last = HEADERS.len() - 1;
    let line = |cells: &[String]| -> String {
        cells
            .iter()
            .enumerate()
            .map(|(i, c)| {
                if i == 0 || i == last {
                    format!("{c:<w$}", w = widths[i])
                } else {
                    format!("{c:>w$}", w = widths[i])
                }
            })
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_string()
    };
    let header: Vec<String> = HEADERS.iter().map(|h| h.to_string()).collect();
    let mut out = line(&header);
    out.push('\n');
    out.push_str(&"-".repeat(widths.iter().sum::<usize>() + 2 * last));
    out.push('\n');
    for row in rows {
        out.push_str(&line(row));
        out.push('\n');
    }
    out
}

/// Markdown table.
pub fn markdown(rows: &[Vec<String>]) -> String {
    let mut out = format!("| {} |\n", HEADERS.join(" | "));
    out.push_str(&format!(
        "|{}\n",
        HEADERS
            .iter()
            .enumerate()
            .map(|(i, _)| if i == 0 || i == HEADERS.len() - 1 {
                "---|"
            } else {
                "---:|"
            })
            .collect::<String>()
    ));
    for row in rows {
        let escaped: Vec<String> = row.iter().map(|c| c.replace('|', "\\|")).collect();
        out.push_str(&format!("| {} |\n", escaped.join(" | ")));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aligned_columns_line_up_and_markdown_has_a_separator_per_column() {
        let rows = vec![
            vec!["a".to_string(); HEADERS.len()],
            vec!["longer cell".to_string(); HEADERS.len()],
        ];
        let text = aligned(&rows);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        // Right-aligned numeric columns end at the same place on every row.
        let col_end = |l: &str| l.find("ms/step").map(|i| i + "ms/step".len());
        let end = col_end(lines[0]).unwrap();
        assert!(end <= lines[2].len() && end <= lines[3].len());
        let md = markdown(&rows);
        assert_eq!(
            md.lines().nth(1).unwrap().matches('|').count(),
            HEADERS.len() + 1
        );
    }
}
