//! Finds where a field path (`bodies[1].colliders[0].shape.radius`) sits in the text of a RON or
//! JSON scene file, so errors found after parsing still name a line.
//!
//! A small scanner over the text: it skips whitespace, comments and strings, matches brackets,
//! and walks the path one segment at a time (a key inside a struct or map, an index inside a
//! list). When a segment is not found it returns the position of the deepest one that was.

/// One step of a field path.
#[derive(Debug, Clone, PartialEq)]
enum Seg<'a> {
    Key(&'a str),
    Index(usize),
}

fn segments(path: &str) -> Vec<Seg<'_>> {
    let mut out = Vec::new();
    for part in path.split('.').filter(|p| !p.is_empty()) {
        let (key, rest) = match part.find('[') {
            Some(k) => (&part[..k], &part[k..]),
            None => (part, ""),
        };
        if !key.is_empty() {
            out.push(Seg::Key(key));
        }
        for idx in rest.split('[').filter(|s| !s.is_empty()) {
            if let Ok(i) = idx.trim_end_matches(']').parse() {
                out.push(Seg::Index(i));
            }
        }
    }
    out
}

struct Scan<'a> {
    b: &'a [u8],
}

impl Scan<'_> {
    /// Skips whitespace and comments from `i`.
    fn ws(&self, mut i: usize) -> usize {
        let b = self.b;
        loop {
            while i < b.len() && b[i].is_ascii_whitespace() {
                i += 1;
            }
            if b[i..].starts_with(b"//") {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            } else if b[i..].starts_with(b"#![") {
                // a RON attribute such as `#![enable(implicit_some)]`
                while i < b.len() && b[i] != b']' {
                    i += 1;
                }
                i = (i + 1).min(b.len());
            } else if b[i..].starts_with(b"/*") {
                i += 2;
                while i < b.len() && !b[i..].starts_with(b"*/") {
                    i += 1;
                }
                i = (i + 2).min(b.len());
            } else {
                return i;
            }
        }
    }

    /// End of the string starting at `i` (a `"`).
    fn string_end(&self, mut i: usize) -> usize {
        i += 1;
        while i < self.b.len() {
            match self.b[i] {
                b'\\' => i += 2,
                b'"' => return i + 1,
                _ => i += 1,
            }
        }
        self.b.len()
    }

    /// End of the value starting at `i`: up to the `,` or closing bracket at its own depth.
    fn value_end(&self, mut i: usize) -> usize {
        let mut depth = 0i32;
        while i < self.b.len() {
            i = self.ws(i);
            if i >= self.b.len() {
                break;
            }
            match self.b[i] {
                b'"' => {
                    i = self.string_end(i);
                    continue;
                }
                b'(' | b'[' | b'{' => depth += 1,
                b')' | b']' | b'}' => {
                    if depth == 0 {
                        return i;
                    }
                    depth -= 1;
                }
                b',' if depth == 0 => return i,
                _ => {}
            }
            i += 1;
        }
        i
    }

    /// Position just inside the opening bracket of the value at `i` (skipping a RON struct or
    /// variant name), or None if the value is not bracketed.
    fn open(&self, i: usize) -> Option<usize> {
        let mut i = self.ws(i);
        while i < self.b.len() && (self.b[i].is_ascii_alphanumeric() || self.b[i] == b'_') {
            i += 1;
        }
        i = self.ws(i);
        matches!(self.b.get(i), Some(b'(' | b'[' | b'{')).then_some(i + 1)
    }

    /// Start of each element (or `key: value` entry) inside the bracket opened at `i`.
    fn elements(&self, i: usize) -> Vec<usize> {
        let mut out = Vec::new();
        let mut j = self.ws(i);
        while j < self.b.len() && !matches!(self.b[j], b')' | b']' | b'}') {
            out.push(j);
            j = self.value_end(j);
            if self.b.get(j) == Some(&b',') {
                j = self.ws(j + 1);
            }
        }
        out
    }

    /// The value of `key` among the entries inside the bracket opened at `i`.
    fn key(&self, i: usize, key: &str) -> Option<usize> {
        for e in self.elements(i) {
            let (name_end, name) = if self.b[e] == b'"' {
                let end = self.string_end(e);
                (end, &self.b[e + 1..end - 1])
            } else {
                let mut k = e;
                while k < self.b.len() && (self.b[k].is_ascii_alphanumeric() || self.b[k] == b'_') {
                    k += 1;
                }
                (k, &self.b[e..k])
            };
            let c = self.ws(name_end);
            if name == key.as_bytes() && self.b.get(c) == Some(&b':') {
                return Some(self.ws(c + 1));
            }
        }
        None
    }
}

/// 1-based `(line, column)` of the value at `path` in `text`; the deepest segment found when
/// the whole path is not there (the whole scene when not even the first is); `None` only for
/// an empty text.
pub(crate) fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    let s = Scan { b: text.as_bytes() };
    let mut at = s.ws(0);
    if at >= text.len() {
        return None;
    }
    let mut found = Some(at);
    for seg in segments(path) {
        let inner = s.open(at)?;
        let next = match seg {
            Seg::Key(k) => s.key(inner, k).or_else(|| {
                // JSON's externally tagged enums: {"Ball": {"radius": …}}
                let e = s.elements(inner);
                let only = *e.first()?;
                let v = s.value_end(only);
                let colon = text[only..v].find(':')? + only;
                let inner2 = s.open(colon + 1)?;
                s.key(inner2, k)
            }),
            Seg::Index(n) => s.elements(inner).get(n).copied(),
        };
        match next {
            Some(n) => {
                at = n;
                found = Some(n);
            }
            None => break,
        }
    }
    let pos = found?;
    let line = text[..pos].matches('\n').count() + 1;
    let col = pos - text[..pos].rfind('\n').map_or(0, |k| k + 1) + 1;
    Some((line, col))
}

#[cfg(test)]
mod tests {
    use super::locate;

    #[test]
    fn finds_ron_and_json_fields() {
        let ron = "#![enable(implicit_some)]\n(\n  name: \"x\", // a comment with ( and \"\n  bodies: [\n    (name: \"a\", colliders: []),\n    (name: \"b\",\n     colliders: [(shape: Ball(radius: -1))]),\n  ],\n)";
        assert_eq!(
            locate(ron, "bodies[1].colliders[0].shape.radius"),
            Some((7, 39))
        );
        assert_eq!(locate(ron, "bodies[1]"), Some((6, 5)));
        assert_eq!(locate(ron, "name"), Some((3, 9)));
        let json = "{\n \"bodies\": [\n  {\"name\": \"a\"},\n  {\"colliders\": [{\"shape\": {\"Ball\": {\"radius\": -1}}}]}\n ]\n}";
        assert_eq!(
            locate(json, "bodies[1].colliders[0].shape.radius"),
            Some((4, 48))
        );
        // a missing tail gives the deepest part found
        assert_eq!(locate(json, "bodies[1].nothing"), Some((4, 3)));
        assert_eq!(locate(json, "nothing"), Some((1, 1)));
        assert_eq!(locate("  ", "nothing"), None);
    }
}
