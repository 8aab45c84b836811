//! Where in a PLY file a problem is: the header line of an element, or the start of one of
//! its rows (a line of an ASCII payload, a byte offset in a binary one), so that errors found
//! after parsing still say `FILE:LINE` or `FILE: byte N`.

use ply_rs_bw::ply::{Encoding, Header, PropertyType, ScalarType};

/// A place in a PLY file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Place {
    /// A 1-based line (the header, or an ASCII payload row).
    Line(usize),
    /// A 0-based byte offset (a binary payload row, or where it ended).
    Byte(usize),
}

/// The 1-based line of `element NAME` in the header text `head`, else the header's last line
/// (`end_header`).
pub(crate) fn element_line(head: &[u8], name: &str) -> usize {
    let text = String::from_utf8_lossy(head);
    text.lines()
        .position(|l| {
            let mut words = l.split_whitespace();
            words.next() == Some("element") && words.next() == Some(name)
        })
        .map_or_else(|| header_lines(head), |i| i + 1)
}

/// The lines of the header `head` (its last, `end_header`, included).
pub(crate) fn header_lines(head: &[u8]) -> usize {
    head.iter().filter(|&&b| b == b'\n').count().max(1)
}

/// Where row `row` of element `name` starts. ASCII rows are lines after the header; binary
/// rows are walked from the payload's start (`rest`), reading each list's count. `None`
/// when the element does not exist or the payload ends before the row.
pub(crate) fn row_place(
    header: &Header,
    head: &[u8],
    rest: &[u8],
    name: &str,
    row: usize,
) -> Option<Place> {
    let big = match header.encoding {
        Encoding::Ascii => {
            let before: usize = header
                .elements
                .values()
                .take_while(|e| e.name != name)
                .map(|e| e.count)
                .sum();
            return Some(Place::Line(header_lines(head) + before + row + 1));
        }
        Encoding::BinaryBigEndian => true,
        Encoding::BinaryLittleEndian => false,
    };
    let mut at = 0usize;
    for e in header.elements.values() {
        for r in 0..e.count {
            if e.name == name && r == row {
                return Some(Place::Byte(head.len() + at));
            }
            for p in e.properties.values() {
                at = match &p.data_type {
                    PropertyType::Scalar(s) => at + size(s),
                    PropertyType::List(c, item) => {
                        let n = count(rest.get(at..at + size(c))?, c, big)?;
                        at.checked_add(size(c))?
                            .checked_add(n.checked_mul(size(item))?)?
                    }
                };
                if at > rest.len() {
                    return None;
                }
            }
        }
    }
    None
}

/// The bytes of a binary scalar.
pub(crate) fn size(s: &ScalarType) -> usize {
    match s {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// A list's count, stored as `c` in `bytes` (a negative or float count: `None`).
fn count(bytes: &[u8], c: &ScalarType, big: bool) -> Option<usize> {
    let mut b = [0u8; 4];
    let n = bytes.len();
    b[..n].copy_from_slice(bytes);
    if big {
        b[..n].reverse();
    }
    let v = u32::from_le_bytes(b) as i64;
    let v = match c {
        ScalarType::Char => v as u8 as i8 as i64,
        ScalarType::Short => v as u16 as i16 as i64,
        ScalarType::Int => v as u32 as i32 as i64,
        ScalarType::Float | ScalarType::Double => return None,
        _ => v,
    };
    usize::try_from(v).ok()
}
