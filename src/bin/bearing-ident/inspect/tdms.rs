//! `inspect` of TDMS files: groups and channels with their properties.

use std::fmt::Write as _;

use bearing_ident::tdms::{Channel, Property, TdmsFile, Value};
use serde_json::{Map, Value as Json, json};

/// Properties as a JSON object (numbers as numbers, the rest as text).
fn properties(ps: &[Property]) -> Json {
    let map: Map<String, Json> = ps
        .iter()
        .map(|p| {
            let v = match &p.value {
                Value::Int(v) => json!(v),
                Value::Uint(v) => json!(v),
                Value::Float(v) => json!(v),
                Value::Bool(v) => json!(v),
                other => json!(other.to_string()),
            };
            (p.name.clone(), v)
        })
        .collect();
    Json::Object(map)
}

/// A TDMS file as JSON: `file`, `properties`, `groups` (each `name`, `properties`,
/// `channels`: `name`, `data_type`, `n`, `unit`, `unreadable`, `properties`).
pub fn json(path: &str, file: &TdmsFile) -> Json {
    let channel = |c: &Channel| {
        json!({
            "name": c.name,
            "data_type": c.data_type,
            "n": c.values.len(),
            "unit": c.unit(),
            "unreadable": c.unreadable,
            "properties": properties(&c.properties),
        })
    };
    let groups: Vec<Json> = file
        .groups
        .iter()
        .map(|g| {
            json!({
                "name": g.name,
                "properties": properties(&g.properties),
                "channels": g.channels.iter().map(channel).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({ "file": path, "properties": properties(&file.properties), "groups": groups })
}

/// A TDMS file as a table: one line per channel (group, name, samples, unit, rate), its
/// properties below it.
pub fn table(path: &str, file: &TdmsFile) -> String {
    let mut s = String::new();
    let channels: usize = file.groups.iter().map(|g| g.channels.len()).sum();
    let _ = writeln!(
        s,
        "{path}: TDMS, {} group{}, {channels} channel{}",
        file.groups.len(),
        if file.groups.len() == 1 { "" } else { "s" },
        if channels == 1 { "" } else { "s" }
    );
    let list = |s: &mut String, indent: &str, ps: &[Property]| {
        for p in ps {
            let _ = writeln!(s, "{indent}{} = {}", p.name, p.value);
        }
    };
    list(&mut s, "  ", &file.properties);
    for g in &file.groups {
        let _ = writeln!(s, "  group `{}`", g.name);
        list(&mut s, "    ", &g.properties);
        for c in &g.channels {
            let rate = bearing_ident::tdms::property(&c.properties, "wf_increment")
                .and_then(Value::as_f64)
                .map_or_else(String::new, |dt| format!(", {} Hz", 1.0 / dt));
            let what = match &c.unreadable {
                Some(why) => why.clone(),
                None => format!("{} samples", c.values.len()),
            };
            let _ = writeln!(
                s,
                "    channel `{}`: {what}{rate}, unit {}",
                c.name,
                c.unit().unwrap_or("(none)")
            );
            list(&mut s, "      ", &c.properties);
        }
    }
    s
}
