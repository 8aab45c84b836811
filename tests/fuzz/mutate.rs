//! The fuzzer's mutator: structure-aware edits of a scene file's bytes, deterministic from a
//! seed. Text formats get edits of their numbers, names, lines and bracketed spans; binary
//! ones (GLB, binary PLY, glTF buffers) get edits of aligned integers and floats; all get
//! truncation, byte flips, deletions and splices from another seed file.

/// SplitMix64: a small, fast, seedable generator (the sequence is part of a case's identity).
pub struct Rng(u64);

impl Rng {
    /// The generator for `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed ^ 0x5851_f42d_4c95_7f2d)
    }
    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
    /// True with probability 1 / n.
    pub fn one_in(&mut self, n: usize) -> bool {
        self.below(n) == 0
    }
    /// One of `items`.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Numbers that break code: bounds of integer types, huge and tiny floats, non-finite ones.
const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "3",
    "7",
    "255",
    "256",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "4294967297",
    "9223372036854775807",
    "18446744073709551616",
    "-2147483648",
    "-9223372036854775808",
    "-9223372036854775809",
    "18446744073709551615",
    "-0",
    "1e30",
    "-1e30",
    "1e-30",
    "1e38",
    "3.5e38",
    "1e308",
    "1e400",
    "-1e400",
    "1e-400",
    "4.9e-324",
    "1.7976931348623157e308",
    "1e99999",
    "1e-99999",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "0.0",
    "-0.0",
    "0.5",
    "1.5",
    "16384",
    "16385",
    "1000000",
    "100000000",
    "0x10",
    "1e",
    "--1",
    "1.2.3",
    "",
];

/// 32-bit patterns for binary files: counts, offsets, and float bit patterns.
const WORDS: &[u32] = &[
    0,
    1,
    2,
    3,
    4,
    0xff,
    0x100,
    0xffff,
    0x10000,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0xffff_fffe,
    0x7fc0_0000,
    0x7f80_0000,
    0xff80_0000,
    0x7f7f_ffff,
    0x0000_0001,
    0x3f80_0000,
    0xbf80_0000,
    0x7149_f2ca,
    5120,
    5121,
    5122,
    5123,
    5125,
    5126,
    34962,
    34963,
];

/// Most bytes one repetition or nesting edit may add (edits compound, so this bounds a case's
/// size at a few MiB rather than letting three edits multiply it a million times).
const GROWTH: usize = 1 << 20;

/// Bytes that mean something in one of the formats.
const BYTES: &[u8] = b"\0\xff\x80\"<>/{}[],:$=\n\r\t #.-e\\";

/// Whether `bytes` look like text (the edits of numbers and names then apply).
fn is_text(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(512)];
    head.iter()
        .all(|&b| b == b'\n' || b == b'\r' || b == b'\t' || (32..127).contains(&b))
}

/// `bytes` after one to three edits (mostly one), each chosen by `rng`; `donor` is another
/// seed file of the same format that splices take their bytes from. A GLB file's JSON chunk
/// is edited as text and the container's lengths rewritten, half the time.
pub fn mutate(bytes: &[u8], donor: &[u8], rng: &mut Rng) -> Vec<u8> {
    if let Some((json, bin)) = glb_chunks(bytes) {
        if rng.one_in(2) {
            let json = mutate(&json, donor, rng);
            return glb(&json, &bin);
        }
    }
    let mut out = bytes.to_vec();
    let edits = *rng.pick(&[1, 1, 1, 2, 3]);
    for _ in 0..edits {
        if is_text(&out) {
            text_edit(&mut out, donor, rng);
        } else {
            binary_edit(&mut out, donor, rng);
        }
    }
    out
}

/// One edit of a text file: mostly of a number, an index or a name, which keep the syntax.
fn text_edit(b: &mut Vec<u8>, donor: &[u8], rng: &mut Rng) {
    match rng.below(27) {
        0..=5 => number(b, rng),
        6..=8 => small_index(b, rng),
        9 | 10 => swap_word(b, rng),
        11 | 12 => nest(b, rng),
        13 | 14 => duplicate_span(b, rng),
        15 => truncate(b, rng),
        16 => flip(b, rng),
        17 => delete(b, rng),
        18 => splice(b, donor, rng),
        19 => set_byte(b, rng),
        20 | 21 => extreme_integer(b, rng),
        22 | 23 => control_char(b, rng),
        _ => node_list(b, rng),
    }
}

/// One edit of a binary file: mostly an aligned integer or float.
fn binary_edit(b: &mut Vec<u8>, donor: &[u8], rng: &mut Rng) {
    match rng.below(10) {
        0..=4 => binary_word(b, rng),
        5 => flip(b, rng),
        6 => truncate(b, rng),
        7 => delete(b, rng),
        8 => splice(b, donor, rng),
        _ => duplicate_span(b, rng),
    }
}

/// A GLB file's JSON and BIN chunk payloads (BIN empty when absent).
fn glb_chunks(b: &[u8]) -> Option<(Vec<u8>, Vec<u8>)> {
    let word = |at: usize| Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?) as usize);
    if b.get(..4) != Some(b"glTF") {
        return None;
    }
    let json_len = word(12)?;
    let json = b.get(20..20 + json_len)?.to_vec();
    let bin_at = 20 + json_len;
    let bin = match word(bin_at) {
        Some(n) => b.get(bin_at + 8..bin_at + 8 + n)?.to_vec(),
        None => Vec::new(),
    };
    Some((json, bin))
}

/// A GLB file of a JSON and a BIN chunk, each padded to 4 bytes.
pub fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |v: &[u8], with: u8| {
        let mut v = v.to_vec();
        v.resize(v.len().div_ceil(4) * 4, with);
        v
    };
    let (json, bin) = (pad(json, b' '), pad(bin, 0));
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    if !bin.is_empty() {
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(&bin);
    }
    out
}

/// Cuts the file at a random point.
fn truncate(b: &mut Vec<u8>, rng: &mut Rng) {
    let at = rng.below(b.len() + 1);
    b.truncate(at);
}

/// Flips one to eight random bits.
fn flip(b: &mut [u8], rng: &mut Rng) {
    for _ in 0..1 + rng.below(8) {
        if b.is_empty() {
            return;
        }
        let i = rng.below(b.len());
        b[i] ^= 1 << rng.below(8);
    }
}

/// Sets a random byte to one that means something.
fn set_byte(b: &mut [u8], rng: &mut Rng) {
    if !b.is_empty() {
        let i = rng.below(b.len());
        b[i] = *rng.pick(BYTES);
    }
}

/// A random span `a..b` of `len` bytes, at most `max` long.
fn span(len: usize, max: usize, rng: &mut Rng) -> (usize, usize) {
    let a = rng.below(len + 1);
    let n = rng.below(max.min(len - a) + 1);
    (a, a + n)
}

/// Deletes a short span.
fn delete(b: &mut Vec<u8>, rng: &mut Rng) {
    let (x, y) = span(b.len(), 64, rng);
    b.drain(x..y);
}

/// Replaces a span with one of the donor's.
fn splice(b: &mut Vec<u8>, donor: &[u8], rng: &mut Rng) {
    let (x, y) = span(b.len(), 128, rng);
    let (p, q) = span(donor.len(), 256, rng);
    b.splice(x..y, donor[p..q].iter().copied());
}

/// Repeats a span (a line of a text file, else any bytes) from 2 to 1000 times.
fn duplicate_span(b: &mut Vec<u8>, rng: &mut Rng) {
    let (x, y) = if is_text(b) && !b.is_empty() {
        line_at(b, rng.below(b.len()))
    } else {
        span(b.len(), 64, rng)
    };
    let piece = b[x..y].to_vec();
    let times = (*rng.pick(&[1usize, 2, 3, 10, 100, 1000])).min(GROWTH / piece.len().max(1));
    let copies: Vec<u8> = std::iter::repeat_n(piece, times).flatten().collect();
    b.splice(y..y, copies);
}

/// The line (with its newline) that holds byte `i`.
fn line_at(b: &[u8], i: usize) -> (usize, usize) {
    let start = b[..i]
        .iter()
        .rposition(|&c| c == b'\n')
        .map_or(0, |p| p + 1);
    let end = b[i..]
        .iter()
        .position(|&c| c == b'\n')
        .map_or(b.len(), |p| i + p + 1);
    (start, end)
}

/// Writes an interesting 8, 16 or 32-bit value at a 4-byte aligned offset.
fn binary_word(b: &mut [u8], rng: &mut Rng) {
    if b.len() < 4 {
        return flip(b, rng);
    }
    let at = rng.below(b.len() / 4) * 4;
    let w = *rng.pick(WORDS);
    match rng.below(3) {
        0 => b[at..at + 4].copy_from_slice(&w.to_le_bytes()),
        1 => b[at..at + 2].copy_from_slice(&(w as u16).to_le_bytes()),
        _ => b[at] = w as u8,
    }
}

/// The spans of the numbers in a text (digits with a sign, point and exponent).
fn numbers(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() {
            let mut start = i;
            if start > 0 && b[start - 1] == b'-' {
                start -= 1;
            }
            while i < b.len() && (b[i].is_ascii_digit() || b"eE.+-".contains(&b[i])) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// Replaces a number by one that breaks code, or by itself scaled.
fn number(b: &mut Vec<u8>, rng: &mut Rng) {
    let spans = numbers(b);
    if spans.is_empty() {
        return flip(b, rng);
    }
    let (x, y) = *rng.pick(&spans);
    let new = if rng.one_in(4) {
        let v: f64 = std::str::from_utf8(&b[x..y])
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1.0);
        let f = *rng.pick(&[-1.0, 2.0, 10.0, 1e6, 1e-6, 0.0]);
        format!("{}", v * f)
    } else {
        rng.pick(NUMBERS).to_string()
    };
    b.splice(x..y, new.into_bytes());
}

/// Replaces a small integer (an index, a count) by a nearby one.
fn small_index(b: &mut Vec<u8>, rng: &mut Rng) {
    let spans: Vec<_> = numbers(b)
        .into_iter()
        .filter(|&(x, y)| y - x <= 2)
        .collect();
    if spans.is_empty() {
        return number(b, rng);
    }
    let (x, y) = *rng.pick(&spans);
    let new = rng.below(12).to_string();
    b.splice(x..y, new.into_bytes());
}

/// The spans of the words (letters, digits, `_`) that start with a letter.
fn words(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_alphabetic() && (i == 0 || !b[i - 1].is_ascii_alphanumeric()) {
            let s = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

/// Replaces a word (a key, a type, a name) with another word of the same file.
fn swap_word(b: &mut Vec<u8>, rng: &mut Rng) {
    let spans = words(b);
    if spans.len() < 2 {
        return flip(b, rng);
    }
    let (x, y) = *rng.pick(&spans);
    let (p, q) = *rng.pick(&spans);
    let new = b[p..q].to_vec();
    b.splice(x..y, new);
}

/// The bracketed span (`{..}`, `[..]` or an XML element `<a ..>..</a>`) that opens at `i`.
fn bracketed(b: &[u8], i: usize) -> Option<(usize, usize)> {
    let (open, close) = match b[i] {
        b'{' => (b'{', b'}'),
        b'[' => (b'[', b']'),
        b'<' if b.get(i + 1).is_some_and(u8::is_ascii_alphabetic) => return element(b, i),
        _ => return None,
    };
    let mut depth = 0usize;
    for (j, &c) in b.iter().enumerate().skip(i) {
        if c == open {
            depth += 1;
        } else if c == close {
            depth -= 1;
            if depth == 0 {
                return Some((i, j + 1));
            }
        }
    }
    None
}

/// The XML element that opens at `i` (up to its matching close tag, or its `/>`).
fn element(b: &[u8], i: usize) -> Option<(usize, usize)> {
    let name_end = i + 1 + b[i + 1..].iter().position(|c| !c.is_ascii_alphanumeric())?;
    let name = &b[i + 1..name_end];
    let tag_end = i + b[i..].iter().position(|&c| c == b'>')?;
    if b[tag_end - 1] == b'/' {
        return Some((i, tag_end + 1));
    }
    let close = [b"</", name, b">"].concat();
    let at = b[tag_end..]
        .windows(close.len())
        .position(|w| w == close.as_slice())?;
    Some((i, tag_end + at + close.len()))
}

/// Nests or repeats a bracketed span: a JSON object or array, or an XML element, is copied
/// into itself (deeper nesting) or next to itself (more items), up to 100 times.
fn nest(b: &mut Vec<u8>, rng: &mut Rng) {
    let opens: Vec<usize> = (0..b.len()).filter(|&i| b"{[<".contains(&b[i])).collect();
    if opens.is_empty() {
        return duplicate_span(b, rng);
    }
    let Some((x, y)) = bracketed(b, *rng.pick(&opens)) else {
        return;
    };
    let piece = b[x..y].to_vec();
    let times = (*rng.pick(&[1usize, 2, 10, 100])).min(GROWTH / piece.len().max(1));
    if rng.one_in(2) {
        // Next to itself, comma-separated in JSON.
        let sep: &[u8] = if piece[0] == b'<' { b"" } else { b"," };
        let mut add = Vec::new();
        for _ in 0..times {
            add.extend_from_slice(sep);
            add.extend_from_slice(&piece);
        }
        b.splice(y..y, add);
    } else {
        // Inside itself, just after its opening bracket or tag, `times` levels deep (in a
        // JSON object as the value of a key, in an array as its first item).
        let at = match piece[0] {
            b'<' => piece.iter().position(|&c| c == b'>').map_or(1, |p| p + 1),
            _ => 1,
        };
        let (pre, post): (&[u8], &[u8]) = match piece[0] {
            b'{' => (b"\"n\":", b","),
            b'[' => (b"", b","),
            _ => (b"", b""),
        };
        let mut nested = piece.clone();
        for _ in 1..=times {
            nested = [&piece[..at], pre, &nested, post, &piece[at..]].concat();
        }
        b.splice(x..y, nested);
    }
}

/// Integers at the bounds of the types parsers read them into, and just past them. i64::MIN,
/// whose negation and absolute value overflow, comes up most often.
const EXTREME_INTEGERS: &[&str] = &[
    "-9223372036854775808",
    "-9223372036854775808",
    "-9223372036854775808",
    "-9223372036854775807",
    "9223372036854775807",
    "-9223372036854775809",
    "9223372036854775808",
    "18446744073709551615",
    "18446744073709551616",
    "-18446744073709551615",
    "-2147483648",
    "2147483647",
    "4294967295",
    "-0",
];

/// Replaces an integer (an index, a count, a size) by an extreme one, half the time every
/// integer on its line (all of a face's corner indices, all of a list's numbers).
fn extreme_integer(b: &mut Vec<u8>, rng: &mut Rng) {
    let ints: Vec<(usize, usize)> = numbers(b)
        .into_iter()
        .filter(|&(x, y)| b[x..y].iter().all(|&c| c.is_ascii_digit() || c == b'-'))
        .collect();
    if ints.is_empty() {
        return number(b, rng);
    }
    let (x, y) = *rng.pick(&ints);
    let value = rng.pick(EXTREME_INTEGERS).as_bytes();
    let targets: Vec<(usize, usize)> = if rng.one_in(2) {
        let (start, end) = line_at(b, x);
        ints.into_iter()
            .filter(|&(p, q)| p >= start && q <= end)
            .collect()
    } else {
        vec![(x, y)]
    };
    for &(p, q) in targets.iter().rev() {
        b.splice(p..q, value.iter().copied());
    }
}

/// Control characters as XML writes them in an attribute: character references (a literal
/// tab or newline there reads as a space), C1 controls and DEL included.
const XML_CONTROLS: &[&str] = &[
    "&#9;",
    "&#10;",
    "&#13;",
    "&#9;&#10;",
    "&#x85;",
    "&#x7f;",
    "&#x9b;",
    "&#x1b;",
];

/// Control characters as JSON and TOML strings write them: escapes.
const ESCAPED_CONTROLS: &[&str] = &[
    "\\t", "\\n", "\\r", "\\t\\n", "\\u0000", "\\u0001", "\\u001b", "\\u007f", "\\u0085",
    "\\u2028", "\\u202e",
];

/// Control characters and invalid UTF-8 as raw bytes: C0 and C1 controls, DEL, a bidi
/// override, a lone continuation byte, a truncated sequence, a surrogate, a code point past
/// U+10FFFF.
const RAW_CONTROLS: &[&[u8]] = &[
    b"\t",
    b"\n",
    b"\r",
    b"\0",
    b"\x01",
    b"\x1b",
    b"\x7f",
    b"\xc2\x85",
    b"\xe2\x80\xae",
    b"\xff",
    b"\xc3",
    b"\x80",
    b"\xed\xa0\x80",
    b"\xf4\x90\x80\x80",
];

/// The spans inside double quotes (a string, an attribute's value) that do not cross a line.
fn quoted(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut open = None;
    for (i, &c) in b.iter().enumerate() {
        match (c, open) {
            (b'"', None) => open = Some(i + 1),
            (b'"', Some(x)) => {
                out.push((x, i));
                open = None;
            }
            (b'\n', _) => open = None,
            _ => {}
        }
    }
    out
}

/// Puts a control character or invalid UTF-8 into a name, an id or another string: in the
/// form the file's format reads as that character (XML character references, JSON and TOML
/// escapes) three times in four, else as raw bytes (the only form in OBJ and PLY).
fn control_char(b: &mut Vec<u8>, rng: &mut Rng) {
    let strings = quoted(b);
    let raw = strings.is_empty() || rng.one_in(4);
    let spans = if strings.is_empty() || rng.one_in(4) {
        words(b)
    } else {
        strings
    };
    if spans.is_empty() {
        return set_byte(b, rng);
    }
    let (x, y) = *rng.pick(&spans);
    let at = x + rng.below(y - x + 1);
    let xml = b.iter().find(|c| !c.is_ascii_whitespace()) == Some(&b'<');
    let piece: &[u8] = match (raw, xml) {
        (true, _) => RAW_CONTROLS[rng.below(RAW_CONTROLS.len())],
        (false, true) => rng.pick(XML_CONTROLS).as_bytes(),
        (false, false) => rng.pick(ESCAPED_CONTROLS).as_bytes(),
    };
    b.splice(at..at, piece.iter().copied());
}

/// The insides of a glTF file's node lists (a scene's `nodes`, a node's `children`): flat
/// arrays of integers after those keys.
fn node_lists(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for key in [&b"\"nodes\""[..], b"\"children\""] {
        for at in (0..b.len()).filter(|&i| b[i..].starts_with(key)) {
            let rest = &b[at + key.len()..];
            let skip = |s: &[u8]| s.iter().take_while(|c| c.is_ascii_whitespace()).count();
            let colon = skip(rest);
            if rest.get(colon) != Some(&b':') {
                continue;
            }
            let open = colon + 1 + skip(&rest[colon + 1..]);
            if rest.get(open) != Some(&b'[') {
                continue;
            }
            let Some(len) = rest[open + 1..].iter().position(|&c| c == b']') else {
                continue;
            };
            let inside = &rest[open + 1..open + 1 + len];
            if inside
                .iter()
                .all(|&c| c.is_ascii_digit() || c == b',' || c.is_ascii_whitespace())
            {
                let x = at + key.len() + open + 1;
                out.push((x, x + len));
            }
        }
    }
    out
}

/// Repeats or shares glTF nodes: a node list becomes itself repeated, one of its nodes
/// repeated, or another node of the file (shared with its own parent, or a cycle) repeated,
/// a few times or 20,000 or 50,000 times: 20,000 copies of the 4,096-triangle sphere seed
/// are more triangles than a scene may have (and more bytes than 4 GiB), a few copies a
/// small scene; none in between, whose render would only make the run slower. Other formats
/// get an extreme integer instead.
fn node_list(b: &mut Vec<u8>, rng: &mut Rng) {
    let lists = node_lists(b);
    if lists.is_empty() {
        return extreme_integer(b, rng);
    }
    let (x, y) = *rng.pick(&lists);
    let items = |s: &[u8]| -> Vec<Vec<u8>> {
        s.split(|&c| c == b',')
            .map(|i| i.trim_ascii().to_vec())
            .filter(|i| !i.is_empty())
            .collect()
    };
    let mine = items(&b[x..y]);
    let all: Vec<Vec<u8>> = lists.iter().flat_map(|&(p, q)| items(&b[p..q])).collect();
    let piece: Vec<Vec<u8>> = match rng.below(3) {
        0 if !mine.is_empty() => mine,
        1 if !mine.is_empty() => vec![rng.pick(&mine).clone()],
        _ if !all.is_empty() => vec![rng.pick(&all).clone()],
        _ => vec![b"0".to_vec()],
    };
    let piece = piece.join(&b","[..]);
    let times = *rng.pick(&[2usize, 3, 10, 20_000, 50_000]);
    let times = times.min(GROWTH / (piece.len() + 1)).max(1);
    let mut list = piece.clone();
    for _ in 1..times {
        list.push(b',');
        list.extend_from_slice(&piece);
    }
    b.splice(x..y, list);
}
