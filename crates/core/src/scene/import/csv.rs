//! Light lists: one light a line, `x, y, z, power`, separated by commas, semicolons, tabs
//! or spaces; `#` starts a comment; an optional header line names the columns (`x`, `y`,
//! `z`, `power`, and optionally `name`, in any order). Errors name the line.

use glam::DVec3;

use super::count::check_count;
use super::plane::{IMPORT_PLANE_PIXELS, footprint_plane};
use crate::scene::{Scene, SceneError};

/// The columns of a list: indices of x, y, z, power and (optionally) name.
struct Columns {
    x: usize,
    y: usize,
    z: usize,
    power: usize,
    name: Option<usize>,
    count: usize,
}

impl Columns {
    const PLAIN: Columns = Columns {
        x: 0,
        y: 1,
        z: 2,
        power: 3,
        name: None,
        count: 4,
    };

    /// The columns a header names, or why it cannot be a header.
    fn from_header(fields: &[&str], line: usize) -> Result<Columns, SceneError> {
        let find = |key: &str| {
            fields
                .iter()
                .position(|f| f.trim_matches('"').eq_ignore_ascii_case(key))
        };
        let need = |key: &str| {
            find(key).ok_or_else(|| {
                SceneError::invalid(
                    format!("line {line}"),
                    format!(
                        "a header must name the columns x, y, z and power (no '{key}' in: {})",
                        fields.join(", ")
                    ),
                )
            })
        };
        Ok(Columns {
            x: need("x")?,
            y: need("y")?,
            z: need("z")?,
            power: need("power")?,
            name: find("name"),
            count: fields.len(),
        })
    }
}

/// The fields of a line: split at commas, semicolons and white space (a quoted name may not
/// hold separators).
fn fields(line: &str) -> Vec<&str> {
    line.split(|c: char| c == ',' || c == ';' || c.is_whitespace())
        .filter(|f| !f.is_empty())
        .collect()
}

/// Parses a light list (module docs) into a scene named `name` over its footprint.
pub(super) fn read(bytes: &[u8], name: &str) -> Result<Scene, SceneError> {
    let text = std::str::from_utf8(bytes).map_err(|e| SceneError::Import {
        format: "csv",
        message: format!("not UTF-8 text ({e})"),
    })?;
    // Refuse too many lights before reading any: every content line but a header is one.
    let mut content = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty());
    let header = content
        .next()
        .is_some_and(|first| !fields(first).iter().all(|v| v.parse::<f64>().is_ok()));
    check_count(content.count() + usize::from(!header), "lights")?;
    let mut columns: Option<Columns> = None;
    let mut positions = Vec::new();
    let mut powers = Vec::new();
    let mut names: Vec<Option<String>> = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let content = raw.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let f = fields(content);
        if columns.is_none() {
            if f.iter().all(|v| v.parse::<f64>().is_ok()) {
                columns = Some(Columns::PLAIN);
            } else {
                columns = Some(Columns::from_header(&f, line)?);
                continue;
            }
        }
        let Some(c) = &columns else { continue };
        if f.len() != c.count {
            return Err(SceneError::invalid(
                format!("line {line}"),
                format!(
                    "expected {} fields ({}), found {}",
                    c.count,
                    if c.count == 4 {
                        "x, y, z, power".to_owned()
                    } else {
                        "as the header names them".to_owned()
                    },
                    f.len()
                ),
            ));
        }
        let number = |index: usize, what: &str| -> Result<f64, SceneError> {
            let v: f64 = f[index].parse().map_err(|_| {
                SceneError::invalid(
                    format!("line {line}, {what}"),
                    format!("not a number ('{}')", f[index]),
                )
            })?;
            if !v.is_finite() {
                return Err(SceneError::NotFinite {
                    field: format!("line {line}, {what}"),
                    value: v,
                });
            }
            Ok(v)
        };
        let position = DVec3::new(number(c.x, "x")?, number(c.y, "y")?, number(c.z, "z")?);
        let power = number(c.power, "power")?;
        if power < 0.0 {
            return Err(SceneError::Negative {
                field: format!("line {line}, power"),
                value: power,
            });
        }
        positions.push(position);
        powers.push(power);
        names.push(c.name.map(|i| f[i].trim_matches('"').to_owned()));
    }
    if positions.is_empty() {
        return Err(SceneError::invalid(
            "lights",
            "no lights: expected lines of x, y, z, power",
        ));
    }
    let plane = footprint_plane(&positions, IMPORT_PLANE_PIXELS);
    let mut scene = Scene::from_parts(name, plane, positions, powers)?;
    if names.iter().any(Option::is_some) {
        scene.names = Some(names.into_iter().map(Option::unwrap_or_default).collect());
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_lists_headers_and_comments() {
        let scene = read(b"# lamps\n0 0 1 2\n1,0,1,5 # the second\n\n2;0;1;20\n", "l").unwrap();
        assert_eq!(scene.powers.as_slice(), [2.0, 5.0, 20.0]);
        assert_eq!(scene.positions[1], DVec3::new(1.0, 0.0, 1.0));
        let named = read(b"power,name,x,y,z\n3,Key,0,0,2\n1,Fill,1,1,2\n", "h").unwrap();
        assert_eq!(named.powers.as_slice(), [3.0, 1.0]);
        assert_eq!(named.name_of(1), Some("Fill"));
        assert_eq!(named.positions[0], DVec3::new(0.0, 0.0, 2.0));
    }

    #[test]
    fn bad_lines_are_named() {
        let err = |text: &str| read(text.as_bytes(), "bad").unwrap_err().to_string();
        assert_eq!(
            err("0 0 1 2\n0 0 1\n"),
            "line 2: expected 4 fields (x, y, z, power), found 3"
        );
        assert_eq!(err("0 0 1 2\n0 0 1 -3\n"), "line 2, power: negative (-3)");
        assert_eq!(err("0 0 1 2\n0 0 inf 3\n"), "line 2, z: not finite (inf)");
        assert_eq!(
            err("0 0 1 2\n0 zero 1 3\n"),
            "line 2, y: not a number ('zero')"
        );
        assert!(err("a,b,c\n1,2,3\n").starts_with("line 1: a header must name"));
        assert_eq!(
            err("# nothing\n"),
            "lights: no lights: expected lines of x, y, z, power"
        );
        assert_eq!(
            err("0 0 1 0\n"),
            "lights: all 1 powers are zero: nothing emits light"
        );
    }
}
