//! The shape of a RON text with the byte span of every value: enough to find the value a
//! `--set` path names and to replace or add it in place, keeping the rest of the file (its
//! comments, layout and every other value) exactly as written.
//!
//! Written by hand because the `ron` crate parses into typed values or into `ron::Value`,
//! which keeps no positions and drops struct and variant names (`Box(min: ..)` and
//! `(min: ..)` become the same map), so neither can say where a value sits in the text.
//! This reader only delimits values; the scene parser still judges them.

/// A value and where it sits in the text.
#[derive(Debug)]
pub(super) struct Node {
    /// Byte offset of the value's first character.
    pub start: usize,
    /// Byte offset one past the value's last character.
    pub end: usize,
    /// The name before `(`, or a bare identifier / literal's text.
    pub name: Option<String>,
    /// What is inside.
    pub body: Body,
}

/// The inside of a value.
#[derive(Debug)]
pub(super) enum Body {
    /// A number, identifier, string or character.
    Atom,
    /// `Name(field: value, ..)` or `(field: value, ..)`.
    Fields(Group<(String, Node)>),
    /// `Name(value, ..)`, `(value, ..)` or `[value, ..]`.
    Items(Group<Node>),
    /// `{key: value, ..}`.
    Map,
}

/// The members of a bracketed value.
#[derive(Debug)]
pub(super) struct Group<T> {
    /// The members, in order.
    pub members: Vec<T>,
    /// Byte offset of the closing bracket.
    pub close: usize,
    /// Whether a comma follows the last member.
    pub trailing_comma: bool,
}

/// A syntax problem at a byte offset.
pub(super) type Error = (usize, String);

/// The deepest nesting of brackets read: as deep as the scene parser goes (`ron`'s default
/// recursion limit, 128). The reader recurses per bracket, so without a bound a value nested
/// ten thousand deep (`--set 'end_time=[[[[…]]]]'`) overflowed the stack.
pub(super) const MAX_DEPTH: usize = 128;

/// Reads one value from `text` and checks nothing but blanks and comments follow it.
pub(super) fn parse(text: &str) -> Result<Node, Error> {
    let mut r = Reader {
        text,
        pos: 0,
        depth: 0,
    };
    let node = r.value()?;
    r.blank()?;
    if r.pos < text.len() {
        return Err((r.pos, "expected the end of the text after the value".into()));
    }
    Ok(node)
}

struct Reader<'a> {
    text: &'a str,
    pos: usize,
    /// Brackets open at `pos`.
    depth: usize,
}

/// Characters that end a bare token (number, identifier, `true`, `-inf`, ..).
fn ends_atom(c: char) -> bool {
    c.is_whitespace() || "()[]{},:\"'/".contains(c)
}

impl<'a> Reader<'a> {
    fn rest(&self) -> &'a str {
        &self.text[self.pos..]
    }

    fn peek(&self) -> Option<char> {
        self.rest().chars().next()
    }

    /// Skips whitespace and comments (`// ..` and nested `/* .. */`).
    fn blank(&mut self) -> Result<(), Error> {
        loop {
            let trimmed = self.rest().trim_start();
            self.pos = self.text.len() - trimmed.len();
            if trimmed.starts_with("//") {
                self.pos += trimmed.find('\n').unwrap_or(trimmed.len());
            } else if trimmed.starts_with("/*") {
                self.block_comment()?;
            } else {
                return Ok(());
            }
        }
    }

    fn block_comment(&mut self) -> Result<(), Error> {
        let open = self.pos;
        let mut depth = 0usize;
        while self.pos < self.text.len() {
            let r = self.rest();
            if r.starts_with("/*") {
                depth += 1;
                self.pos += 2;
            } else if r.starts_with("*/") {
                depth -= 1;
                self.pos += 2;
                if depth == 0 {
                    return Ok(());
                }
            } else {
                self.pos += r.chars().next().map_or(1, char::len_utf8);
            }
        }
        Err((open, "unclosed comment".into()))
    }

    fn value(&mut self) -> Result<Node, Error> {
        self.blank()?;
        if self.depth >= MAX_DEPTH {
            return Err((
                self.pos,
                format!("values nested more than {MAX_DEPTH} deep"),
            ));
        }
        self.depth += 1;
        let node = self.value_here();
        self.depth -= 1;
        node
    }

    /// The value at `pos` (blanks skipped), one level deeper.
    fn value_here(&mut self) -> Result<Node, Error> {
        let start = self.pos;
        match self.peek() {
            None => Err((start, "expected a value".into())),
            Some('"') => self.string(start),
            Some('\'') => self.character(start),
            Some('r') if self.rest()[1..].starts_with(['"', '#']) => self.raw_string(start),
            Some('(') => self.group(start, None, ')'),
            Some('[') => self.group(start, None, ']'),
            Some('{') => self.map(start),
            Some(c) if ends_atom(c) => Err((start, format!("expected a value, found `{c}`"))),
            Some(_) => {
                let len = self.rest().find(ends_atom).unwrap_or(self.rest().len());
                let name = self.rest()[..len].to_owned();
                self.pos += len;
                if self.peek() == Some('(') {
                    self.group(start, Some(name), ')')
                } else {
                    Ok(atom(start, self.pos, Some(name)))
                }
            }
        }
    }

    fn string(&mut self, start: usize) -> Result<Node, Error> {
        let mut escaped = false;
        for (k, c) in self.rest().char_indices().skip(1) {
            match c {
                _ if escaped => escaped = false,
                '\\' => escaped = true,
                '"' => {
                    self.pos += k + 1;
                    return Ok(atom(start, self.pos, None));
                }
                _ => {}
            }
        }
        Err((start, "unclosed string".into()))
    }

    fn character(&mut self, start: usize) -> Result<Node, Error> {
        let r = self.rest();
        let close = r[1..].find('\'').filter(|&k| k > 0 && k <= 11);
        match close {
            Some(k) => {
                self.pos += k + 2;
                Ok(atom(start, self.pos, None))
            }
            None => Err((start, "unclosed character".into())),
        }
    }

    fn raw_string(&mut self, start: usize) -> Result<Node, Error> {
        let hashes = self.rest()[1..].chars().take_while(|&c| c == '#').count();
        if !self.rest()[1 + hashes..].starts_with('"') {
            return Err((start, "expected `\"` after `r#`".into()));
        }
        let close = format!("\"{}", "#".repeat(hashes));
        let body = 2 + hashes;
        match self.rest()[body..].find(&close) {
            Some(k) => {
                self.pos += body + k + close.len();
                Ok(atom(start, self.pos, None))
            }
            None => Err((start, "unclosed raw string".into())),
        }
    }

    /// `(..)` or `[..]` after the optional name: named fields when the first member is
    /// `identifier:`, else items.
    fn group(&mut self, start: usize, name: Option<String>, close: char) -> Result<Node, Error> {
        self.pos += 1; // the opening bracket
        self.blank()?;
        let named = close == ')' && self.at_field_name();
        let mut fields = Vec::new();
        let mut items = Vec::new();
        let mut trailing_comma = false;
        loop {
            self.blank()?;
            if self.peek() == Some(close) {
                break;
            }
            let first = fields.is_empty() && items.is_empty();
            if !first && !trailing_comma {
                return Err((self.pos, format!("expected `,` or `{close}`")));
            }
            if named {
                let field = self.field_name()?;
                fields.push((field, self.value()?));
            } else {
                items.push(self.value()?);
            }
            self.blank()?;
            trailing_comma = self.peek() == Some(',');
            if trailing_comma {
                self.pos += 1;
            }
        }
        let close_at = self.pos;
        self.pos += 1;
        let body = if named {
            Body::Fields(Group {
                members: fields,
                close: close_at,
                trailing_comma,
            })
        } else {
            Body::Items(Group {
                members: items,
                close: close_at,
                trailing_comma,
            })
        };
        Ok(Node {
            start,
            end: self.pos,
            name,
            body,
        })
    }

    /// Whether an `identifier :` starts here.
    fn at_field_name(&self) -> bool {
        let r = self.rest();
        let len = r.find(ends_atom).unwrap_or(r.len());
        len > 0
            && r[len..].trim_start().starts_with(':')
            && !r.starts_with(|c: char| c.is_ascii_digit())
    }

    fn field_name(&mut self) -> Result<String, Error> {
        if !self.at_field_name() {
            return Err((self.pos, "expected `field: value`".into()));
        }
        let len = self.rest().find(ends_atom).unwrap_or(0);
        let name = self.rest()[..len].to_owned();
        self.pos += len;
        self.blank()?;
        self.pos += 1; // the colon
        Ok(name)
    }

    fn map(&mut self, start: usize) -> Result<Node, Error> {
        self.pos += 1;
        loop {
            self.blank()?;
            match self.peek() {
                Some('}') => break,
                None => return Err((start, "unclosed `{`".into())),
                _ => {}
            }
            self.value()?;
            self.blank()?;
            if self.peek() != Some(':') {
                return Err((self.pos, "expected `:` in a map".into()));
            }
            self.pos += 1;
            self.value()?;
            self.blank()?;
            if self.peek() == Some(',') {
                self.pos += 1;
            }
        }
        self.pos += 1;
        Ok(Node {
            start,
            end: self.pos,
            name: None,
            body: Body::Map,
        })
    }
}

fn atom(start: usize, end: usize, name: Option<String>) -> Node {
    Node {
        start,
        end,
        name,
        body: Body::Atom,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_keep_their_spans_names_and_members() {
        let text = "Scene( // c\n a: [1, Box(min: [0.0], max: \"x)\"),], /* (/* */) */ b: r#\"y\"#, c: (1, 2) )";
        let n = parse(text).unwrap();
        assert_eq!(n.name.as_deref(), Some("Scene"));
        let Body::Fields(g) = &n.body else { panic!() };
        let names: Vec<_> = g.members.iter().map(|(f, _)| f.as_str()).collect();
        assert_eq!(names, ["a", "b", "c"]);
        let Body::Items(list) = &g.members[0].1.body else {
            panic!()
        };
        assert!(list.trailing_comma);
        assert_eq!(list.members[1].name.as_deref(), Some("Box"));
        assert_eq!(
            &text[list.members[1].start..list.members[1].end],
            "Box(min: [0.0], max: \"x)\")"
        );
        assert_eq!(&text[g.members[1].1.start..g.members[1].1.end], "r#\"y\"#");
        assert!(matches!(g.members[2].1.body, Body::Items(_)));
        assert!(!g.trailing_comma);
    }

    #[test]
    fn broken_text_is_an_error_with_its_place() {
        for (text, at) in [
            ("(a: 1", 5),
            ("(a: 1 b: 2)", 6),
            ("\"abc", 0),
            ("(a: 1) x", 7),
            ("/* (", 0),
        ] {
            let e = parse(text).unwrap_err();
            assert_eq!(e.0, at, "{text}: {e:?}");
        }
        // nesting past the bound is refused where it goes too deep, without a stack overflow
        for (text, at) in [
            ("[".repeat(10_000), MAX_DEPTH),
            (format!("Scene(a: {}", "(".repeat(200)), 9 + MAX_DEPTH - 1),
        ] {
            let e = parse(&text).unwrap_err();
            assert!(e.1.contains("nested more than 128 deep"), "{e:?}");
            assert_eq!(e.0, at, "{text}: {e:?}");
        }
    }
}
