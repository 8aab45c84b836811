//! A PLY mesh's custom attributes, which Mitsuba's `mesh_attribute` texture reads: the
//! `vertex` or `face` properties other than positions, normals, uvs and indices, grouped as
//! Mitsuba 3.9's PLY reader groups them (`src/shapes/ply.h`, `find_other_fields`):
//!
//! - `r g b` (with `a`), or `red green blue` (with `alpha`): `<element>_color`;
//! - then runs of consecutive properties `{prefix}_{c}`, `c` one letter following one of the
//!   sequences `x y z w`, `r g b a`, `0 1 2 3`, `1 2 3 4` from its start, of 1 or 3 fields:
//!   `<element>_{prefix}` (`<element>_{prefix}_color` for `r g b`); a prefix seen before, a run
//!   of 2 or 4 fields or a broken sequence is ignored, as Mitsuba ignores it (with a warning
//!   there).
//!
//! Every field is taken as it is, integers too (not normalised: a `uchar` colour of 255 is
//! 255, as in Mitsuba; `scripts/mitsuba_mesh_attribute_probe.py`).

use ply_rs_bw::ply::{DefaultElement, ElementDef, Property, PropertyType};

/// One attribute: its Mitsuba name (`vertex_color`), the properties it reads and their
/// values, `dim` per row (a vertex, or a face's triangle).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyAttribute {
    /// Mitsuba's name for it: `vertex_...` or `face_...`.
    pub name: String,
    /// Fields per row: 1, 3 or (a colour with alpha) 4.
    pub dim: usize,
    /// `dim` values per row.
    pub values: Vec<f32>,
}

/// The one-letter postfix sequences a grouped attribute's fields follow.
const SEQUENCES: [[char; 4]; 4] = [
    ['x', 'y', 'z', 'w'],
    ['r', 'g', 'b', 'a'],
    ['0', '1', '2', '3'],
    ['1', '2', '3', '4'],
];

/// The attributes of element `def` (`kind` is `vertex` or `face`): each name with the
/// properties it reads, in order. `reserved` are the properties read otherwise.
pub(crate) fn groups(
    kind: &str,
    def: &ElementDef,
    reserved: &[&str],
) -> Vec<(String, Vec<String>)> {
    let has = |n: &str| def.properties.contains_key(n);
    let mut out = Vec::new();
    let mut reserved: Vec<&str> = reserved.to_vec();
    reserved.extend(["r", "g", "b", "a"]);
    for colour in [["r", "g", "b", "a"], ["red", "green", "blue", "alpha"]] {
        if colour[..3].iter().all(|n| has(n)) {
            let fields = colour.iter().filter(|n| has(n)).map(|n| n.to_string());
            out.push((format!("{kind}_color"), fields.collect()));
            reserved.extend(colour);
            break;
        }
    }
    let scalar = |p: &&String| matches!(def.properties[*p].data_type, PropertyType::Scalar(_));
    let names: Vec<&String> = def.properties.keys().filter(scalar).collect();
    let mut seen: Vec<String> = Vec::new();
    // The run being read: its prefix, sequence and fields.
    let mut run: Option<(String, usize, Vec<String>)> = None;
    let flush = |run: &mut Option<(String, usize, Vec<String>)>,
                 out: &mut Vec<(String, Vec<String>)>,
                 seen: &mut Vec<String>| {
        if let Some((prefix, sequence, fields)) = run.take() {
            if fields.len() == 1 || fields.len() == 3 {
                let colour = if sequence == 1 { "_color" } else { "" };
                out.push((format!("{kind}_{prefix}{colour}"), fields));
                seen.push(prefix);
            }
        }
    };
    let mut skip: Option<String> = None;
    for name in names {
        if reserved.contains(&name.as_str()) {
            continue;
        }
        let Some((prefix, postfix)) = name.rsplit_once('_') else {
            flush(&mut run, &mut out, &mut seen);
            continue;
        };
        let mut letters = postfix.chars();
        let (Some(c), None) = (letters.next(), letters.next()) else {
            flush(&mut run, &mut out, &mut seen);
            continue;
        };
        if skip.as_deref() == Some(prefix) {
            continue;
        }
        skip = None;
        if run.as_ref().is_some_and(|r| r.0 != prefix) {
            flush(&mut run, &mut out, &mut seen);
        }
        match &mut run {
            None if seen.iter().any(|s| s == prefix) => skip = Some(prefix.to_string()),
            None => {
                if let Some(sequence) = SEQUENCES.iter().position(|s| s[0] == c) {
                    run = Some((prefix.to_string(), sequence, vec![name.clone()]));
                }
            }
            Some((_, sequence, fields)) => {
                if SEQUENCES[*sequence].get(fields.len()) == Some(&c) {
                    fields.push(name.clone());
                } else {
                    run = None;
                    skip = Some(prefix.to_string());
                }
            }
        }
    }
    flush(&mut run, &mut out, &mut seen);
    out
}

/// The value of scalar property `name` of `row` as Mitsuba 3.9 reads an attribute field: as
/// it is, an integer too (`scripts/mitsuba_mesh_attribute_probe.py`: a `uchar` 255 is 255;
/// Mitsuba warns that colours are expected in [0, 1]). A value that is not finite is kept:
/// it is refused where a texture reads it.
pub(crate) fn field(row: &DefaultElement, name: &str) -> Result<f32, String> {
    Ok(match row.get(name) {
        Some(Property::Float(x)) => *x,
        Some(Property::Double(x)) => *x as f32,
        Some(Property::Char(x)) => *x as f32,
        Some(Property::UChar(x)) => *x as f32,
        Some(Property::Short(x)) => *x as f32,
        Some(Property::UShort(x)) => *x as f32,
        Some(Property::Int(x)) => *x as f32,
        Some(Property::UInt(x)) => *x as f32,
        _ => return Err(format!("property `{name}` is not a number")),
    })
}
