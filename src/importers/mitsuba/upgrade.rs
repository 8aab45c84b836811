//! Scenes written for Mitsuba 0.x: Mitsuba 3 reads a file whose `<scene version>` is below
//! 2.0.0 after an in-memory upgrade, and so do we, file by file (an included file by its
//! own version), before any plugin is read. As Mitsuba 3.9.1 does it (checked against
//! its parser, `scripts/mitsuba_upgrade_probe.py`):
//! - every `name` attribute except a `<default>`'s goes from camelCase to snake_case
//!   ([`snake_case`]: `toWorld` -> `to_world`, `intIOR` -> `int_ior`);
//! - a `diffuse` bsdf's `diffuse_reflectance` becomes `reflectance`;
//! - `uoffset`, `voffset`, `uscale` and `vscale` floats become a `to_uv` transform (the
//!   offset, then the scale).
//!
//! The upgrade rewrites the text without adding or removing a line, so errors still name
//! the file's own lines. A version that is not three numbers is an error, as in Mitsuba;
//! a file without one is read as it is (Mitsuba takes it as the current version).

use crate::error::{Error, Result};
use roxmltree::{Document, Node};
use std::ops::Range;

/// The floats that become a `to_uv` transform, with what each sets: (offset or scale, axis).
const UV_FLOATS: [(&str, bool, usize); 4] = [
    ("uoffset", false, 0),
    ("voffset", false, 1),
    ("uscale", true, 0),
    ("vscale", true, 1),
];

/// Mitsuba's camelCase to snake_case: each run of ASCII capitals that follows a lowercase
/// ASCII letter is lowercased, with an `_` before it (`aBcD` -> `a_bc_d`, `xYZw` ->
/// `x_yzw`); capitals after anything else stay (`ABc`, `a2B`).
pub fn snake_case(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    let mut prev_lower = false;
    let mut in_run = false;
    for c in name.chars() {
        if c.is_ascii_uppercase() && (prev_lower || in_run) {
            if prev_lower {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
            in_run = true;
            prev_lower = false;
        } else {
            out.push(c);
            in_run = false;
            prev_lower = c.is_ascii_lowercase();
        }
    }
    out
}

/// The `version` attribute of `text`'s root `<scene>` as three numbers, if it has one.
fn version(file: &str, root: Node) -> Result<Option<[u64; 3]>> {
    let Some(v) = root.attribute("version") else {
        return Ok(None);
    };
    let parts: Vec<Option<u64>> = v
        .split(['.', ' '])
        .filter(|p| !p.is_empty())
        .map(|p| p.parse().ok())
        .collect();
    match parts[..] {
        [Some(a), Some(b), Some(c)] => Ok(Some([a, b, c])),
        _ => Err(Error::Scene {
            file: file.to_string(),
            line: root.document().text_pos_at(root.range().start).row as usize,
            field: "scene.version".into(),
            message: format!("invalid version `{v}` (expected three numbers, as 3.0.0)"),
        }),
    }
}

/// `text` (the file `file`, parsed as `doc`) upgraded as Mitsuba 3 upgrades a Mitsuba 0.x
/// scene, or `None` when it needs nothing: its version is 2.0.0 or later or absent, its root
/// is not a `<scene>`, or nothing in it changes.
pub(crate) fn upgrade(text: &str, doc: &Document, file: &str) -> Result<Option<String>> {
    let root = doc.root_element();
    if root.tag_name().name() != "scene" {
        return Ok(None);
    }
    match version(file, root)? {
        Some(v) if v < [2, 0, 0] => {}
        _ => return Ok(None),
    }
    let mut edits: Vec<(Range<usize>, String)> = Vec::new();
    for node in doc.descendants().filter(Node::is_element) {
        if let Some(attr) = node.attributes().find(|a| a.name() == "name") {
            // A name written with entities is left as it is (no such names exist).
            let range = attr.range_value();
            let raw_is_value = text.get(range.clone()) == Some(attr.value());
            if node.tag_name().name() != "default" && raw_is_value {
                let mut name = snake_case(attr.value());
                let parent = node.parent_element();
                let in_diffuse = parent.is_some_and(|p| {
                    p.tag_name().name() == "bsdf" && p.attribute("type") == Some("diffuse")
                });
                if in_diffuse && name == "diffuse_reflectance" {
                    name = "reflectance".into();
                }
                if name != attr.value() {
                    edits.push((range, name));
                }
            }
        }
        uv_transform(file, text, node, &mut edits)?;
    }
    if edits.is_empty() {
        return Ok(None);
    }
    edits.sort_by_key(|(r, _)| (r.start, r.end));
    let mut out = String::with_capacity(text.len() + 64);
    let mut at = 0;
    for (range, with) in edits {
        // A name inside a removed float is removed with it.
        if range.start < at {
            continue;
        }
        out.push_str(&text[at..range.start]);
        out.push_str(&with);
        at = range.end;
    }
    out.push_str(&text[at..]);
    Ok(Some(out))
}

/// The edits that turn `node`'s `uoffset`, `voffset`, `uscale` and `vscale` float children
/// into a `to_uv` transform before its end tag (the floats blanked, their lines kept).
fn uv_transform(
    file: &str,
    text: &str,
    node: Node,
    edits: &mut Vec<(Range<usize>, String)>,
) -> Result<()> {
    let (mut offset, mut scale) = ([0.0f64; 2], [1.0f64; 2]);
    let mut blanked = Vec::new();
    for child in node.children().filter(Node::is_element) {
        let name = child.attribute("name").unwrap_or("");
        let Some(&(_, is_scale, axis)) = UV_FLOATS.iter().find(|u| u.0 == name) else {
            continue;
        };
        if child.tag_name().name() != "float" {
            continue;
        }
        let raw = child.attribute("value").unwrap_or("");
        let Ok(value) = raw.trim().parse::<f64>() else {
            return Err(Error::Scene {
                file: file.to_string(),
                line: child.document().text_pos_at(child.range().start).row as usize,
                field: format!("{}.{name}", node.tag_name().name()),
                message: format!("`{raw}` is not a number"),
            });
        };
        match is_scale {
            true => scale[axis] = value,
            false => offset[axis] = value,
        }
        let lines = text[child.range()].matches('\n').count();
        blanked.push((child.range(), "\n".repeat(lines)));
    }
    if blanked.is_empty() {
        return Ok(());
    }
    // The element has children, so it has an end tag, where the transform goes.
    let end = node.range();
    let Some(close) = text[end.clone()].rfind("</") else {
        return Ok(());
    };
    let mut t = String::from(r#"<transform name="to_uv">"#);
    if offset != [0.0; 2] {
        t += &format!(r#"<translate x="{}" y="{}"/>"#, offset[0], offset[1]);
    }
    if scale != [1.0; 2] {
        t += &format!(r#"<scale x="{}" y="{}"/>"#, scale[0], scale[1]);
    }
    t += "</transform>";
    let at = end.start + close;
    edits.append(&mut blanked);
    edits.push((at..at, t));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`upgrade`] of `text`, parsed here.
    fn upgrade_text(text: &str) -> Result<Option<String>> {
        upgrade(text, &Document::parse(text).unwrap(), "a.xml")
    }

    #[test]
    fn names_convert_as_mitsuba_3_converts_them() {
        // Mitsuba 3.9.1's own conversions (scripts/mitsuba_upgrade_probe.py).
        for (old, new) in [
            ("toWorld", "to_world"),
            ("intIOR", "int_ior"),
            ("diffuseReflectance", "diffuse_reflectance"),
            ("aBcD", "a_bc_d"),
            ("xYZwQ", "x_yzw_q"),
            ("aB_cD", "a_b_c_d"),
            ("_aB", "_a_b"),
            ("a2B", "a2B"),
            ("ABc", "ABc"),
            ("max_depth", "max_depth"),
        ] {
            assert_eq!(snake_case(old), new, "{old}");
        }
    }

    #[test]
    fn only_files_before_2_0_0_are_upgraded_and_their_lines_stay() {
        let old = "<scene version=\"0.6.0\">\n<float name=\"farClip\" value=\"1\"/>\n</scene>";
        let up = upgrade_text(old).unwrap().unwrap();
        assert_eq!(up, old.replace("farClip", "far_clip"));
        let new = old.replace("0.6.0", "2.0.0");
        assert_eq!(upgrade_text(&new).unwrap(), None);
        let none = old.replace(" version=\"0.6.0\"", "");
        assert_eq!(upgrade_text(&none).unwrap(), None);
        let bad = old.replace("0.6.0", "0.6");
        let e = upgrade_text(&bad).unwrap_err().to_string();
        assert_eq!(
            e,
            "a.xml:1: scene.version: invalid version `0.6` (expected three numbers, as 3.0.0)"
        );
    }

    #[test]
    fn uv_floats_become_a_to_uv_transform_on_the_same_lines() {
        let old = "<scene version=\"0.5.0\"><texture type=\"checkerboard\">\n\
                   <float name=\"vscale\" value=\"3\"/>\n<float name=\"uoffset\" value=\"0.5\"/>\n\
                   </texture></scene>";
        let up = upgrade_text(old).unwrap().unwrap();
        assert_eq!(
            up,
            "<scene version=\"0.5.0\"><texture type=\"checkerboard\">\n\n\n\
             <transform name=\"to_uv\"><translate x=\"0.5\" y=\"0\"/><scale x=\"1\" y=\"3\"/>\
             </transform></texture></scene>"
        );
    }
}
