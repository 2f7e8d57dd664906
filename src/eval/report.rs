//! The evaluation's outputs: a plain-text table and JSON (`{"rows": [{"setting": …,
//! "style_acc": 0.93, "style_acc_ci": 0.01, …}, …]}`, null where a metric does not apply).

use serde_json::{Map, Value, json};

use super::protocol::{COLUMNS, Row};

/// What was evaluated, recorded beside the rows.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Provenance {
    pub command: String,
    pub weights: String,
    pub classifier: String,
    /// `"heldout"` or the `--content` folder.
    pub contents: String,
    pub num_contents: usize,
    pub num_heldout: usize,
    pub repeats: usize,
    pub seed: u64,
    pub seconds: f64,
}

/// The JSON document.
pub fn to_json(rows: &[Row], provenance: &Provenance) -> Value {
    let rows: Vec<Value> = rows
        .iter()
        .map(|row| {
            let mut m = Map::new();
            m.insert("setting".into(), json!(row.setting));
            for (name, value, ci) in &row.values {
                m.insert((*name).into(), json!(value));
                m.insert(format!("{name}_ci"), json!(ci));
            }
            Value::Object(m)
        })
        .collect();
    json!({ "rows": rows, "provenance": provenance })
}

fn cell(value: Option<f64>, ci: Option<f64>, digits: usize) -> String {
    match (value, ci) {
        (None, _) => "—".into(),
        (Some(v), None) => format!("{v:.digits$}"),
        (Some(v), Some(c)) => format!("{v:.digits$} ± {c:.digits$}"),
    }
}

/// A Markdown table (also readable as plain text).
pub fn to_table(rows: &[Row]) -> String {
    let mut out = String::new();
    out.push_str(&format!("| setting | {} |\n", COLUMNS.join(" | ")));
    out.push_str(&format!("|---|{}\n", "---|".repeat(COLUMNS.len())));
    for row in rows {
        let cells: Vec<String> = row
            .values
            .iter()
            .map(|(name, v, ci)| cell(*v, *ci, if name.ends_with("_cm") || name.starts_with("foot_skate") { 2 } else { 3 }))
            .collect();
        out.push_str(&format!("| {} | {} |\n", row.setting, cells.join(" | ")));
    }
    out
}
