//! The rows as CSV, the format `benches/peers/nexus_scenes.py` writes too.

use super::*;

pub(super) fn csv_escape(field: &str) -> String {
    if field.contains([',', '"', '\n']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_owned()
    }
}

/// Splits CSV text into records of fields (quoted fields, doubled quotes and CRLF as Python's
/// `csv` module writes them).
pub(super) fn parse_csv(text: &str) -> Vec<Vec<String>> {
    let mut records = Vec::new();
    let mut record = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') => quoted = true,
            (false, ',') => record.push(std::mem::take(&mut field)),
            (false, '\r') => {}
            (false, '\n') => {
                record.push(std::mem::take(&mut field));
                records.push(std::mem::take(&mut record));
            }
            (false, c) => field.push(c),
        }
    }
    if !field.is_empty() || !record.is_empty() {
        record.push(field);
        records.push(record);
    }
    records
        .into_iter()
        .filter(|r| !(r.len() == 1 && r[0].trim().is_empty()))
        .collect()
}

/// Rows of a CSV with [`CSV_COLUMNS`] (by name, in any order; missing columns are empty).
pub fn read_csv(path: &Path) -> Result<Vec<Row>, String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("reading {}: {e}", path.display()))?;
    let mut records = parse_csv(&text).into_iter();
    let header: Vec<String> = records
        .next()
        .ok_or_else(|| format!("{} is empty", path.display()))?
        .into_iter()
        .map(|h| h.trim().to_owned())
        .collect();
    for needed in ["scene", "engine", "median_ms"] {
        if !header.iter().any(|h| h == needed) {
            return Err(format!("{}: no column {needed}", path.display()));
        }
    }
    records
        .enumerate()
        .map(|(i, r)| {
            Row::from_fields(&header, &r)
                .map_err(|e| format!("{} line {}: {e}", path.display(), i + 2))
        })
        .collect()
}

pub(super) fn csv_text(rows: &[Row]) -> String {
    let mut text = CSV_COLUMNS.join(",");
    text.push('\n');
    for row in rows {
        let fields: Vec<String> = row.csv_fields().iter().map(|f| csv_escape(f)).collect();
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    text
}
