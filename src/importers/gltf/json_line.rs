//! The line of a glTF item in its JSON text, for error messages: a small scanner that follows
//! a field path (`meshes[0].primitives[1]`, `extensions.KHR_lights_punctual.lights[0]`) through
//! the JSON and returns the 1-based line where the value starts (0 when the path is not found).

/// One step of a field path: an object key or an array index.
#[derive(Debug, PartialEq)]
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

/// Splits `a.b[2]["c"]` into steps.
fn steps(path: &str) -> Vec<Step<'_>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (head, rest) = part.split_once('[').map_or((part, ""), |(h, r)| (h, r));
        if !head.is_empty() {
            out.push(Step::Key(head));
        }
        for index in rest.split('[') {
            let index = index.trim_end_matches(']').trim_matches('"');
            match index.parse() {
                Ok(i) => out.push(Step::Index(i)),
                Err(_) if !index.is_empty() => out.push(Step::Key(index)),
                Err(_) => {}
            }
        }
    }
    out
}

/// The 1-based line of the value at `path` in `json`, or 0 when there is none.
pub(crate) fn line_of(json: &str, path: &str) -> usize {
    let bytes = json.as_bytes();
    let mut pos = 0;
    for step in steps(path) {
        match find(bytes, pos, &step) {
            Some(p) => pos = p,
            None => return 0,
        }
    }
    1 + bytes[..pos].iter().filter(|&&b| b == b'\n').count()
}

fn skip_ws(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && b[i].is_ascii_whitespace() {
        i += 1;
    }
    i
}

/// The end of the string starting at `i` (on its opening quote), after the closing quote.
fn skip_string(b: &[u8], mut i: usize) -> usize {
    i += 1;
    while i < b.len() {
        match b[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    i
}

/// The end of the value starting at `i`.
fn skip_value(b: &[u8], i: usize) -> usize {
    let i = skip_ws(b, i);
    match b.get(i) {
        Some(b'"') => skip_string(b, i),
        Some(b'{') | Some(b'[') => {
            let mut depth = 0usize;
            let mut j = i;
            while j < b.len() {
                match b[j] {
                    b'"' => {
                        j = skip_string(b, j);
                        continue;
                    }
                    b'{' | b'[' => depth += 1,
                    b'}' | b']' => {
                        depth -= 1;
                        if depth == 0 {
                            return j + 1;
                        }
                    }
                    _ => {}
                }
                j += 1;
            }
            j
        }
        _ => {
            let mut j = i;
            while j < b.len() && !matches!(b[j], b',' | b'}' | b']') {
                j += 1;
            }
            j
        }
    }
}

/// The start of the member `step` of the container value at `i`.
fn find(b: &[u8], i: usize, step: &Step) -> Option<usize> {
    let mut i = skip_ws(b, i);
    let open = *b.get(i)?;
    i += 1;
    let mut index = 0;
    loop {
        i = skip_ws(b, i);
        if matches!(b.get(i)?, b'}' | b']') {
            return None;
        }
        let hit = match (open, step) {
            (b'{', Step::Key(key)) => {
                let end = skip_string(b, i);
                let name = std::str::from_utf8(b.get(i + 1..end.saturating_sub(1))?).ok()?;
                i = skip_ws(b, end);
                if b.get(i) != Some(&b':') {
                    return None;
                }
                i += 1;
                name == *key
            }
            (b'[', Step::Index(n)) => *n == index,
            _ => return None,
        };
        let start = skip_ws(b, i);
        if hit {
            return Some(start);
        }
        i = skip_ws(b, skip_value(b, start));
        if b.get(i) == Some(&b',') {
            i += 1;
        }
        index += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_nested_items() {
        let json = "{\n \"a\": [1,\n {\"b\": \"x]\"},\n {\"c\": [5,\n 6]}],\n \"d\": 2\n}";
        assert_eq!(line_of(json, "a[1]"), 3);
        assert_eq!(line_of(json, "a[2].c[1]"), 5);
        assert_eq!(line_of(json, "d"), 6);
        assert_eq!(line_of(json, "a[7]"), 0);
        assert_eq!(line_of(json, "e"), 0);
        let want = [Step::Key("m"), Step::Index(0), Step::Key("attributes")];
        assert_eq!(steps("m[0].attributes[\"POSITION\"]")[..3], want);
        assert_eq!(
            steps("m[0].attributes[\"POSITION\"]")[3],
            Step::Key("POSITION")
        );
    }
}
