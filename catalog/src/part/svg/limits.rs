//! Bounds on the work and memory an SVG file can make the reader spend,
//! whatever the file: checked on the bytes before the XML parser builds
//! anything (size, elements, attributes, entity expansion), and while
//! walking and flattening (nesting depth, path commands, vertices). Real
//! drawings of parts stay orders of magnitude below every one of them.

/// Largest SVG part file read, bytes.
pub(super) const MAX_BYTES: usize = 32 << 20;
/// Most elements (start tags) in a file.
pub(super) const MAX_ELEMENTS: usize = 500_000;
/// Most attributes in a file.
pub(super) const MAX_ATTRIBUTES: usize = 2_000_000;
/// Deepest nesting of elements walked.
pub(super) const MAX_DEPTH: usize = 1_000;
/// Most path commands, all `d` attributes together.
pub(super) const MAX_PATH_COMMANDS: usize = 2_000_000;
/// Most vertices drawn (curves after flattening), all shapes together.
pub(super) const MAX_VERTICES: usize = 2_000_000;
/// Most bytes all entity references of the file may expand to: the
/// internal entities real files declare (Illustrator's namespace names)
/// come to a few hundred bytes; a "billion laughs" file to gigabytes.
pub(super) const MAX_ENTITY_EXPANSION: usize = 1 << 20;

/// A bound of this module exceeded: what was counted and the bound; it
/// becomes the `TooBig` of [`SvgError`](super::SvgError) or
/// [`PathError`](super::PathError).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Exceeded {
    pub(super) what: &'static str,
    pub(super) limit: usize,
}

/// Why the bytes are refused before parsing; becomes an
/// [`SvgError`](super::SvgError).
#[derive(Debug)]
pub(super) enum PrescanRefusal {
    Exceeded(Exceeded),
    EntityLoop(String),
    ExternalEntity {
        name: String,
        kind: &'static str,
        uri: String,
    },
}

/// What the walk may still spend; shared by every element of a file.
pub(super) struct Budget {
    commands: usize,
    vertices: usize,
}

impl Budget {
    pub(super) fn new() -> Self {
        Budget {
            commands: MAX_PATH_COMMANDS,
            vertices: MAX_VERTICES,
        }
    }

    /// Spends one path command.
    pub(super) fn command(&mut self) -> Result<(), Exceeded> {
        spend(
            &mut self.commands,
            1,
            "path commands in the file",
            MAX_PATH_COMMANDS,
        )
    }

    /// Spends `count` vertices.
    pub(super) fn vertices(&mut self, count: usize) -> Result<(), Exceeded> {
        spend(
            &mut self.vertices,
            count,
            "vertices in the file (curves flattened)",
            MAX_VERTICES,
        )
    }
}

fn spend(left: &mut usize, count: usize, what: &'static str, limit: usize) -> Result<(), Exceeded> {
    *left = left.checked_sub(count).ok_or(Exceeded { what, limit })?;
    Ok(())
}

/// Checks the raw text against the bounds that must hold before the XML
/// parser allocates: size, start tags, attributes, and entity expansion
/// (`roxmltree` expands internal entities itself, with a reference-count
/// guard per top-level reference that still lets a small file grow
/// quadratically; it never reads external ones, but a reference to one
/// would fail with a less helpful message).
pub(super) fn prescan(text: &str) -> Result<(), PrescanRefusal> {
    let limit = |what, limit| PrescanRefusal::Exceeded(Exceeded { what, limit });
    if text.len() > MAX_BYTES {
        return Err(limit("bytes in an SVG file", MAX_BYTES));
    }
    let (elements, attributes) = count_tags(text.as_bytes());
    if elements > MAX_ELEMENTS {
        return Err(limit("elements in the file", MAX_ELEMENTS));
    }
    if attributes > MAX_ATTRIBUTES {
        return Err(limit("attributes in the file", MAX_ATTRIBUTES));
    }
    check_entities(text)
}

/// Upper bounds on start tags (`<` before a name) and attributes (`=`
/// signs): no quote or comment can hide one from this count, which only
/// errs on the safe side (an `=` in text counts as an attribute).
fn count_tags(bytes: &[u8]) -> (usize, usize) {
    let elements = bytes
        .windows(2)
        .filter(|w| w[0] == b'<' && (w[1].is_ascii_alphabetic() || w[1] == b'_' || w[1] >= 0x80))
        .count();
    let attributes = bytes.iter().filter(|&&c| c == b'=').count();
    (elements, attributes)
}

/// A general entity of the internal DTD subset.
enum XmlEntity<'a> {
    /// Replacement text, as written (references unexpanded).
    Internal(&'a str),
    /// `SYSTEM "uri"` or `PUBLIC "id" "uri"`.
    External(&'static str, &'a str),
}

/// Declarations `<!ENTITY name ...>` (parameter entities, `%`, are not
/// expanded by the parser and are skipped).
fn declarations(text: &str) -> Vec<(&str, XmlEntity<'_>)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("<!ENTITY") {
        rest = &rest[at + "<!ENTITY".len()..];
        let t = rest.trim_start();
        if t.starts_with('%') {
            continue;
        }
        let name_end = t.find(|c: char| c.is_whitespace()).unwrap_or(t.len());
        let (name, t) = (&t[..name_end], t[name_end..].trim_start());
        let entity = if let Some(after) = t.strip_prefix("SYSTEM") {
            quoted(after.trim_start()).map(|(v, _)| XmlEntity::External("SYSTEM", v))
        } else if let Some(after) = t.strip_prefix("PUBLIC") {
            quoted(after.trim_start())
                .and_then(|(_, rest)| quoted(rest.trim_start()))
                .map(|(v, _)| XmlEntity::External("PUBLIC", v))
        } else {
            quoted(t).map(|(v, _)| XmlEntity::Internal(v))
        };
        if let Some(e) = entity {
            out.push((name, e));
        }
    }
    out
}

/// A quoted string at the start of `text`: its text and what follows it.
fn quoted(text: &str) -> Option<(&str, &str)> {
    let q = text.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    let end = text[1..].find(q)? + 1;
    Some((&text[1..end], &text[end + 1..]))
}

/// The names of the `&name;` references in `text` (character references
/// and the five predefined entities are not expanded beyond one byte and
/// are left out).
fn references(text: &str) -> impl Iterator<Item = &str> {
    text.match_indices('&').filter_map(move |(i, _)| {
        let r = &text[i + 1..];
        let end = r.find(';')?;
        let name = &r[..end];
        let plain = !name.is_empty()
            && !name.starts_with('#')
            && !matches!(name, "lt" | "gt" | "amp" | "apos" | "quot")
            && name
                .chars()
                .all(|c| c.is_alphanumeric() || "_-.:".contains(c));
        plain.then_some(name)
    })
}

/// Bounds what all entity references of the document expand to, and
/// refuses references to external entities.
fn check_entities(text: &str) -> Result<(), PrescanRefusal> {
    if !text.contains("<!ENTITY") {
        return Ok(());
    }
    let decls = declarations(text);
    let too_much = || {
        PrescanRefusal::Exceeded(Exceeded {
            what: "bytes of entity expansion",
            limit: MAX_ENTITY_EXPANSION,
        })
    };
    // Expanded sizes, saturating at the bound; the first declaration of a
    // name counts, as in XML.
    let mut sizes: std::collections::HashMap<&str, Option<usize>> = Default::default();
    fn size<'a>(
        name: &'a str,
        decls: &[(&'a str, XmlEntity<'a>)],
        sizes: &mut std::collections::HashMap<&'a str, Option<usize>>,
        stack: &mut Vec<&'a str>,
    ) -> Result<usize, PrescanRefusal> {
        if let Some(s) = sizes.get(name) {
            return s.ok_or_else(|| PrescanRefusal::EntityLoop(name.to_string()));
        }
        let Some((_, e)) = decls.iter().find(|(n, _)| *n == name) else {
            return Ok(0);
        };
        let value = match e {
            XmlEntity::Internal(v) => *v,
            XmlEntity::External(kind, uri) => {
                return Err(PrescanRefusal::ExternalEntity {
                    name: name.to_string(),
                    kind,
                    uri: uri.to_string(),
                })
            }
        };
        if stack.len() > 64 {
            return Err(PrescanRefusal::EntityLoop(name.to_string()));
        }
        sizes.insert(name, None);
        stack.push(name);
        let mut total = value.len();
        for r in references(value) {
            total = total.saturating_add(size(r, decls, sizes, stack)?);
            if total > MAX_ENTITY_EXPANSION {
                break;
            }
        }
        stack.pop();
        let total = total.min(MAX_ENTITY_EXPANSION + 1);
        sizes.insert(name, Some(total));
        Ok(total)
    }
    // References outside entity values: after the internal subset.
    // (The first `]>` after the DOCTYPE may be inside a value; counting
    // from too early only counts more.)
    let body = text
        .find("<!DOCTYPE")
        .and_then(|d| text[d..].find("]>").map(|i| &text[d + i..]))
        .unwrap_or(text);
    let mut total = 0usize;
    let mut stack = Vec::new();
    for r in references(body) {
        total = total.saturating_add(size(r, &decls, &mut sizes, &mut stack)?);
        if total > MAX_ENTITY_EXPANSION {
            return Err(too_much());
        }
    }
    Ok(())
}
