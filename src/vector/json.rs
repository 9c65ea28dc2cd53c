//! The JSON form of a [`VectorLayer`] (documented in the module docs), with serde.
//!
//! Colours and edge references are checked while parsing, so serde_json's error carries the
//! line and column; unknown keys are errors (`deny_unknown_fields`), so a typo such as
//! `"raduis"` is reported instead of silently giving a mark of radius 0.

use super::{Edge, PointMark, Polyline, Rgba, Stroke, VectorLayer};
use crate::error::Error;
use serde::Deserialize;
use serde_json::Value;
use std::collections::HashMap;
use std::path::Path;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLayer {
    #[serde(default)]
    points: Vec<RawPoint>,
    #[serde(default)]
    polylines: Vec<RawPolyline>,
    #[serde(default)]
    edges: Vec<RawEdge>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPoint {
    #[serde(default)]
    id: Option<String>,
    x: f64,
    y: f64,
    #[serde(alias = "radius")]
    r: f64,
    #[serde(default)]
    fill: Option<Colour>,
    #[serde(default)]
    stroke: Option<Colour>,
    #[serde(default)]
    stroke_width: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPolyline {
    points: Vec<[f64; 2]>,
    #[serde(default)]
    width: Option<f64>,
    #[serde(default, alias = "colour")]
    color: Option<Colour>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEdge {
    from: Ref,
    to: Ref,
    #[serde(default)]
    width: Option<f64>,
    #[serde(default, alias = "colour")]
    color: Option<Colour>,
}

/// A colour, checked while parsing.
#[derive(Deserialize)]
#[serde(try_from = "Value")]
struct Colour(Rgba);

impl TryFrom<Value> for Colour {
    type Error = String;
    fn try_from(v: Value) -> Result<Colour, String> {
        let bad = |v: &Value| {
            format!(
                "{v} is not a colour: give \"#rgb\", \"#rrggbb\", \"#rrggbbaa\", or [r, g, b] or \
                 [r, g, b, a] with whole numbers 0 to 255"
            )
        };
        match &v {
            Value::String(s) => parse_hex(s).map(Colour).ok_or_else(|| bad(&v)),
            Value::Array(a) if a.len() == 3 || a.len() == 4 => {
                let mut c = [0, 0, 0, 255];
                for (k, x) in a.iter().enumerate() {
                    c[k] = x.as_u64().filter(|&n| n <= 255).ok_or_else(|| bad(&v))? as u8;
                }
                Ok(Colour(c))
            }
            _ => Err(bad(&v)),
        }
    }
}

fn parse_hex(s: &str) -> Option<Rgba> {
    let h = s.strip_prefix('#')?;
    if !h.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let byte = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok();
    let nibble = |i: usize| u8::from_str_radix(&h[i..i + 1], 16).ok().map(|n| n * 17);
    Some(match h.len() {
        3 => [nibble(0)?, nibble(1)?, nibble(2)?, 255],
        4 => [nibble(0)?, nibble(1)?, nibble(2)?, nibble(3)?],
        6 => [byte(0)?, byte(2)?, byte(4)?, 255],
        8 => [byte(0)?, byte(2)?, byte(4)?, byte(6)?],
        _ => return None,
    })
}

/// An edge's end: a point's index or id.
#[derive(Deserialize)]
#[serde(try_from = "Value")]
enum Ref {
    Index(usize),
    Id(String),
}

impl TryFrom<Value> for Ref {
    type Error = String;
    fn try_from(v: Value) -> Result<Ref, String> {
        match v {
            Value::String(s) => Ok(Ref::Id(s)),
            Value::Number(n) if n.as_u64().is_some() => {
                Ok(Ref::Index(n.as_u64().unwrap_or_default() as usize))
            }
            other => Err(format!(
                "{other} does not name a point: give its \"id\" or its index in \"points\" (0, 1, ...)"
            )),
        }
    }
}

const BLACK: Rgba = [0, 0, 0, 255];
const DEFAULT_WIDTH: f64 = 1.0;

/// Parses one layer from JSON text; the message says where a problem is (line and column)
/// and what was expected.
pub fn parse_layer(text: &str) -> Result<VectorLayer, String> {
    let raw: RawLayer =
        serde_json::from_str(text).map_err(|e| format!("{e}{}", not_json_number(text, &e)))?;
    let layer = resolve(raw)?;
    layer.validate()?;
    Ok(layer)
}

/// Parses one line of JSON Lines, numbered `line` (from 1): the message starts with the line
/// number, and the column is that of the line.
pub(crate) fn parse_line(text: &str, line: usize) -> Result<VectorLayer, String> {
    let raw: RawLayer = serde_json::from_str(text).map_err(|e| {
        let msg = e.to_string();
        let msg = msg
            .rsplit_once(" at line ")
            .map_or(msg.as_str(), |(m, _)| m)
            .to_string();
        format!(
            "line {line}, column {}: {msg}{}",
            e.column(),
            not_json_number(text, &e)
        )
    })?;
    let layer = resolve(raw).map_err(|m| format!("line {line}: {m}"))?;
    layer.validate().map_err(|m| format!("line {line}: {m}"))?;
    Ok(layer)
}

/// A hint when serde_json stopped at `NaN` or `Infinity`: JSON has neither, but some writers
/// (Python's `json.dumps`) emit them, and "expected value" alone does not say why.
fn not_json_number(text: &str, e: &serde_json::Error) -> &'static str {
    let line = text.lines().nth(e.line().saturating_sub(1)).unwrap_or("");
    let at = line
        .get(e.column().saturating_sub(1)..)
        .unwrap_or("")
        .trim_start_matches('-');
    if at.starts_with("NaN") || at.starts_with("Infinity") {
        " (JSON has no NaN or Infinity: give a number, or leave the mark out)"
    } else {
        ""
    }
}

/// Parses JSON Lines text into one layer per non-blank line.
pub fn parse_layer_lines(text: &str) -> Result<Vec<VectorLayer>, String> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| parse_line(l, i + 1))
        .collect()
}

/// Whether `path` names a JSON Lines file (`.jsonl` or `.ndjson`).
pub(crate) fn is_json_lines(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("jsonl") || e.eq_ignore_ascii_case("ndjson"))
}

/// Reads one layer from a file: a JSON document, or for JSON Lines (`.jsonl`, `.ndjson`) its
/// first non-blank line (the layer of frame 0). Errors name the file.
pub fn read_layer(path: &Path) -> Result<VectorLayer, Error> {
    let text = read_text(path)?;
    if is_json_lines(path) {
        return match text.lines().enumerate().find(|(_, l)| !l.trim().is_empty()) {
            Some((i, l)) => parse_line(l, i + 1).map_err(|m| Error::decode(path, m)),
            None => Err(Error::decode(path, "holds no line of marks")),
        };
    }
    parse_layer(&text).map_err(|m| Error::decode(path, m))
}

/// A file's text; not UTF-8 is a decode error naming the file.
pub(crate) fn read_text(path: &Path) -> Result<String, Error> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| {
        Error::decode(
            path,
            format!(
                "is not UTF-8 text (byte {} of the file): marks are JSON",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// The layer with defaults filled in and edges resolved to point indices.
fn resolve(raw: RawLayer) -> Result<VectorLayer, String> {
    let mut ids: HashMap<&str, usize> = HashMap::new();
    for (i, p) in raw.points.iter().enumerate() {
        if let Some(id) = &p.id {
            if let Some(j) = ids.insert(id.as_str(), i) {
                return Err(format!(
                    "points[{i}]: id \"{id}\" is already the id of points[{j}]"
                ));
            }
        }
    }
    let n = raw.points.len();
    let find = |r: &Ref, i: usize, end: &str| -> Result<usize, String> {
        match r {
            Ref::Index(k) if *k < n => Ok(*k),
            Ref::Index(k) => Err(format!(
                "edges[{i}]: \"{end}\" is point {k}, but there are {n} points (indices 0 to {})",
                n.saturating_sub(1)
            )),
            Ref::Id(s) => ids.get(s.as_str()).copied().ok_or_else(|| {
                format!("edges[{i}]: \"{end}\" names \"{s}\", but no point has that id")
            }),
        }
    };
    let edges = raw
        .edges
        .iter()
        .enumerate()
        .map(|(i, e)| {
            Ok(Edge {
                from: find(&e.from, i, "from")?,
                to: find(&e.to, i, "to")?,
                width: e.width.unwrap_or(DEFAULT_WIDTH),
                color: e.color.as_ref().map_or(BLACK, |c| c.0),
            })
        })
        .collect::<Result<Vec<Edge>, String>>()?;
    let points = raw
        .points
        .into_iter()
        .map(|p| PointMark {
            id: p.id,
            x: p.x,
            y: p.y,
            radius: p.r,
            fill: p.fill.map_or(BLACK, |c| c.0),
            stroke: p.stroke.map(|c| Stroke {
                color: c.0,
                width: p.stroke_width.unwrap_or(DEFAULT_WIDTH),
            }),
        })
        .collect();
    let polylines = raw
        .polylines
        .into_iter()
        .map(|l| Polyline {
            points: l.points,
            width: l.width.unwrap_or(DEFAULT_WIDTH),
            color: l.color.map_or(BLACK, |c| c.0),
        })
        .collect();
    Ok(VectorLayer {
        points,
        polylines,
        edges,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_documented_example_parses() {
        let text = r##"{
          "points": [
            {"id": "paris", "x": 412.5, "y": 160, "r": 6, "fill": "#d7191c",
             "stroke": "#ffffff", "stroke_width": 1.5},
            {"x": 300, "y": 200, "radius": 4, "fill": [44, 123, 182, 200]}
          ],
          "polylines": [
            {"points": [[10, 300], [120, 250], [240, 280]], "width": 2, "color": "#333333"}
          ],
          "edges": [
            {"from": "paris", "to": 1, "width": 1.5, "colour": "#55555580"}
          ]
        }"##;
        let l = parse_layer(text).unwrap();
        assert_eq!(l.points.len(), 2);
        assert_eq!(l.points[0].fill, [0xd7, 0x19, 0x1c, 255]);
        assert_eq!(
            l.points[0].stroke,
            Some(Stroke {
                color: [255; 4],
                width: 1.5
            })
        );
        assert_eq!(l.points[1].fill, [44, 123, 182, 200]);
        assert_eq!(l.points[1].radius, 4.0);
        assert_eq!(l.polylines[0].points.len(), 3);
        assert_eq!(
            l.edges[0],
            Edge {
                from: 0,
                to: 1,
                width: 1.5,
                color: [0x55, 0x55, 0x55, 0x80]
            }
        );
        assert_eq!(parse_layer("{}").unwrap(), VectorLayer::default());
        assert_eq!(parse_hex("#abc"), Some([0xaa, 0xbb, 0xcc, 255]));
    }

    #[test]
    fn errors_say_where_and_what() {
        let e = parse_layer("{\n\"points\": [\n{\"x\": 1, \"y\": 2, \"raduis\": 3}]}").unwrap_err();
        assert!(e.contains("raduis") && e.contains("line 3"), "{e}");
        let e =
            parse_layer(r#"{"points": [{"x": 1, "y": 2, "r": 3, "fill": "red"}]}"#).unwrap_err();
        assert!(e.contains("\"red\" is not a colour"), "{e}");
        let e = parse_layer(r#"{"points": [{"x": 1, "y": 2, "r": -3}]}"#).unwrap_err();
        assert!(e.contains("points[0]: radius -3"), "{e}");
        let e = parse_layer(
            r#"{"points": [{"x": 1, "y": 2, "r": 3}], "edges": [{"from": 0, "to": "b"}]}"#,
        )
        .unwrap_err();
        assert!(e.contains("edges[0]") && e.contains("\"b\""), "{e}");
        let e = parse_layer(
            r#"{"points": [{"x": 1, "y": 2, "r": 3}], "edges": [{"from": 0, "to": 4}]}"#,
        )
        .unwrap_err();
        assert!(e.contains("point 4, but there are 1 points"), "{e}");
        let e = parse_layer(r#"{"polylines": [{"points": []}]}"#).unwrap_err();
        assert!(e.contains("polylines[0]: has no points"), "{e}");
        let e = parse_layer_lines("{}\n\n{\"points\": [}\n").unwrap_err();
        assert!(e.starts_with("line 3, column"), "{e}");
        assert!(!e.contains("at line"), "{e}");
        assert_eq!(parse_layer_lines("{}\n\n{}\n").unwrap().len(), 2);
        for bad in ["NaN", "Infinity", "-Infinity"] {
            let text = format!("{{\"points\": [{{\"x\": {bad}, \"y\": 2, \"r\": 3}}]}}");
            let e = parse_layer(&text).unwrap_err();
            assert!(e.contains("JSON has no NaN"), "{bad}: {e}");
            let e = parse_layer_lines(&format!("{{}}\n{text}")).unwrap_err();
            assert!(
                e.starts_with("line 2") && e.contains("JSON has no NaN"),
                "{e}"
            );
        }
        let e = parse_layer(r#"{"points": [{"x": Nope, "y": 2, "r": 3}]}"#).unwrap_err();
        assert!(!e.contains("NaN"), "{e}");
        let e = parse_layer(r#"{"points": [{"x": 1, "y": 2, "r": 1e300}]}"#).unwrap_err();
        assert!(e.contains("radius 1e300 is out of range"), "{e}");
    }
}
