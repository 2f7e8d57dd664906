//! The evaluation's outputs: plain-text tables and JSON (`{"rows": [{"setting": …,
//! "style_acc": 0.93, "style_acc_ci": 0.01, …}, …], "labels": [{"setting", "style", "outputs",
//! "style_acc", "style_shift", "content_acc", "content_mistakes": [{"content", "taken_for",
//! "count"}, …]}, …], "directions": …}`, null where a metric does not apply).

use serde_json::{Map, Value, json};

use super::protocol::{COLUMNS, Evaluation, PartShift, Row};
use super::shift::{DESCRIPTORS, Direction, Directions};

/// What was evaluated, recorded beside the rows.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Provenance {
    pub command: String,
    pub weights: String,
    pub classifier: String,
    /// The content classifier, if one was used.
    pub content_classifier: Option<String>,
    /// `"heldout"` or the `--content` folder.
    pub contents: String,
    pub num_contents: usize,
    pub num_heldout: usize,
    pub repeats: usize,
    pub seed: u64,
    pub seconds: f64,
}

/// The JSON document; `styles`: the label names, by index.
pub fn to_json(
    eval: &Evaluation,
    directions: Option<&Directions>,
    styles: &[String],
    provenance: &Provenance,
) -> Value {
    let rows: Vec<Value> = eval
        .rows
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
    let name = |i: usize| styles.get(i).cloned().unwrap_or_else(|| i.to_string());
    let labels: Vec<Value> = eval
        .labels
        .iter()
        .map(|l| {
            json!({"setting": l.setting, "style": name(l.style), "outputs": l.outputs,
                   "style_acc": l.style_acc, "style_shift": l.style_shift, "content_acc": l.content_acc,
                   "content_mistakes": l.content_mistakes})
        })
        .collect();
    let directions = directions.map(|d| {
        let styles: Vec<Value> = d
            .styles
            .iter()
            .map(|s| {
                json!({"style": name(s.style), "contents": s.contents, "takes": s.takes, "length": s.length,
                       "scored": s.scored, "vector": s.vector})
            })
            .collect();
        json!({"descriptors": DESCRIPTORS, "spread": d.spread, "styles": styles})
    });
    let mut doc = json!({ "rows": rows, "labels": labels, "directions": directions, "provenance": provenance });
    if !eval.parts.is_empty() {
        doc["parts"] = json!(eval.parts);
    }
    doc
}

/// The directions back from [`to_json`]'s `"directions"` (as `make eval` commits them in
/// `assets/eval/heldout.json`), style names resolved against `styles`; `None` if the value is not
/// such an object, names descriptors other than [`DESCRIPTORS`] or a style `styles` lacks.
pub fn directions_from_json(value: &Value, styles: &[String]) -> Option<Directions> {
    let names: Vec<&str> = value.get("descriptors")?.as_array()?.iter().map(|v| v.as_str()).collect::<Option<_>>()?;
    if names != DESCRIPTORS {
        return None;
    }
    let numbers = |v: &Value| -> Option<Vec<f64>> { v.as_array()?.iter().map(Value::as_f64).collect() };
    let spread = numbers(value.get("spread")?)?;
    let styles = value
        .get("styles")?
        .as_array()?
        .iter()
        .map(|s| {
            let name = s.get("style")?.as_str()?;
            Some(Direction {
                style: styles.iter().position(|x| x == name)?,
                contents: usize::try_from(s.get("contents")?.as_u64()?).ok()?,
                takes: usize::try_from(s.get("takes")?.as_u64()?).ok()?,
                vector: numbers(s.get("vector")?).filter(|v| v.len() == DESCRIPTORS.len())?,
                length: s.get("length")?.as_f64()?,
                scored: s.get("scored")?.as_bool()?,
            })
        })
        .collect::<Option<Vec<_>>>()?;
    (spread.len() == DESCRIPTORS.len()).then_some(Directions { spread, styles })
}

/// Per target label: each row's style accuracy and style shift (`—`: not measured or the style is
/// not scored), with a content classifier its content accuracy, and the direction's length in
/// spreads.
pub fn labels_table(eval: &Evaluation, directions: Option<&Directions>, styles: &[String]) -> String {
    let settings: Vec<&str> = {
        let mut v: Vec<&str> = eval.labels.iter().map(|l| l.setting).collect();
        v.dedup();
        v
    };
    let with_content = eval.labels.iter().any(|l| l.content_acc.is_some());
    let mut out = String::from("| label | direction |");
    for s in &settings {
        out.push_str(&format!(" {s} acc | {s} shift |"));
        if with_content {
            out.push_str(&format!(" {s} content |"));
        }
    }
    let per_setting = if with_content { "---|---|---|" } else { "---|---|" };
    out.push_str(&format!("\n|---|---|{}\n", per_setting.repeat(settings.len())));
    let mut label_ids: Vec<usize> = eval.labels.iter().map(|l| l.style).collect();
    label_ids.sort_unstable();
    label_ids.dedup();
    for style in label_ids {
        let name = styles.get(style).map_or("?", String::as_str);
        let dir = directions
            .and_then(|d| d.get(style))
            .map_or("—".into(), |d| format!("{:.2}{}", d.length, if d.scored { "" } else { " (not scored)" }));
        out.push_str(&format!("| {name} | {dir} |"));
        for s in &settings {
            let l = eval.labels.iter().find(|l| l.setting == *s && l.style == style);
            let acc = cell(l.and_then(|l| l.style_acc), None, 3);
            let shift = cell(l.and_then(|l| l.style_shift), None, 2);
            out.push_str(&format!(" {acc} | {shift} |"));
            if with_content {
                out.push_str(&format!(" {} |", cell(l.and_then(|l| l.content_acc), None, 3)));
            }
        }
        out.push('\n');
    }
    out
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
            .map(|(name, v, ci)| {
                let digits = if name.ends_with("_cm") || name.starts_with("foot_skate") || *name == "style_shift" {
                    2
                } else {
                    3
                };
                cell(*v, *ci, digits)
            })
            .collect();
        out.push_str(&format!("| {} | {} |\n", row.setting, cells.join(" | ")));
    }
    out
}

/// The per-part table ([`PartShift`]): per variant, the style shift on the lower body's and the
/// upper body's descriptors.
pub fn parts_table(parts: &[PartShift]) -> String {
    let f = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.2}"));
    let mut out = String::from(
        "| label-based, style on | outputs | shift (lower-body descriptors) | shift (upper-body descriptors) |\n|---|---|---|---|\n",
    );
    for p in parts {
        out.push_str(&format!("| {} | {} | {} | {} |\n", p.variant, p.outputs, f(p.lower), f(p.upper)));
    }
    out
}
