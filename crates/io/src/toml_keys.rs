//! Unknown keys and values in a TOML file. serde refuses them as "unknown
//! field `x`, expected one of `a`, `b`" or "unknown variant `x`, expected
//! ..."; here that becomes an error naming the key or value, its line, the
//! table it is in and the nearest valid one:
//!
//! ```text
//! model.toml:19: unknown key `shear_aera_y` in [[section]] 'web'; did you
//! mean `shear_area_y`? (valid keys: `area`, `iy`, ...)
//! ```
//!
//! serde's error carries a span, but for an internally tagged table (a
//! `[[section]]` by `shape`, an `[[element]]` by `type`) it is the span of the
//! whole table, not of the key. So the key is looked up in a tree of the
//! document's keys and values with their spans: the first key (or string
//! value) of that name inside the span, or in the table the span is.

use crate::spelling::nearest;
use crate::{InputError, TomlSource};
use serde::de::{Deserialize, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use toml::Spanned;

/// The error for a TOML text that `T` could not be read from: an unknown
/// key or value named with its line, table and nearest valid spelling;
/// any other error with its line.
pub(crate) fn error(src: &TomlSource<'_>, e: &toml::de::Error) -> InputError {
    let span = e.span();
    let Some(refused) = Refused::from_message(e.message()) else {
        return src.error(span.map(|s| s.start), e.message().to_string());
    };
    let tree: Option<Spanned<Node>> = toml::from_str(src.text).ok();
    let hit = match (&tree, &span) {
        (Some(tree), Some(span)) => find(tree, &refused, span, &mut Vec::new()),
        _ => None,
    };
    match hit {
        Some(hit) => src.error(Some(hit.offset), refused.message(&hit.place(refused.kind))),
        None => src.error(span.map(|s| s.start), refused.message("")),
    }
}

/// Refuses the first top-level key of `src` (in the order of the text) that
/// is not in `known`, naming its line and the nearest of `known`.
pub(crate) fn refuse_unknown_top_level(
    src: &TomlSource<'_>,
    known: &[&str],
) -> Result<(), InputError> {
    let keys: BTreeMap<Spanned<String>, IgnoredAny> = src.parse()?;
    let unknown = keys
        .keys()
        .filter(|k| !known.contains(&k.get_ref().as_str()))
        .min_by_key(|k| k.span().start);
    match unknown {
        None => Ok(()),
        Some(key) => {
            let refused = Refused {
                kind: Kind::Key,
                name: key.get_ref().clone(),
                expected: known.iter().map(|k| k.to_string()).collect(),
            };
            Err(src.error(Some(key.span().start), refused.message(" at the top level")))
        }
    }
}

/// The largest magnitude a number in a TOML file may have: as in every
/// file flexbody reads, [`flexbody_linalg::dense_check::LARGEST`].
pub const LARGEST_NUMBER: f64 = flexbody_linalg::dense_check::LARGEST;

/// Refuses the first number of `src` (in the order of the text) that is
/// not finite (`nan`, `inf`) or larger in magnitude than
/// [`LARGEST_NUMBER`], naming its line, key and table.
pub(crate) fn refuse_out_of_range(src: &TomlSource<'_>) -> Result<(), InputError> {
    let Ok(tree) = toml::from_str::<Spanned<Node>>(src.text) else {
        return Ok(());
    };
    let mut path = Vec::new();
    match out_of_range(&tree, &mut path) {
        None => Ok(()),
        Some((value, hit)) => {
            let problem = if value.is_finite() {
                format!(
                    "is beyond {LARGEST_NUMBER:e} in magnitude (no SI quantity of a model is \
                     that large, and its products overflow)"
                )
            } else {
                "is not a finite number".to_string()
            };
            Err(src.error(
                Some(hit.offset),
                format!("{value:e}{} {problem}", hit.place(Kind::Value)),
            ))
        }
    }
}

/// The first float below `node` (in the text's order) that is not finite
/// or too large, and where it is.
fn out_of_range<'a>(
    node: &'a Spanned<Node>,
    path: &mut Vec<(Step<'a>, &'a Spanned<Node>)>,
) -> Option<(f64, Hit<'a>)> {
    let children: Vec<(Step<'a>, &'a Spanned<Node>)> = match node.get_ref() {
        Node::Float(v) if v.is_nan() || v.abs() > LARGEST_NUMBER => {
            let hit = Hit {
                offset: node.span().start,
                path: path.clone(),
            };
            return Some((*v, hit));
        }
        Node::Table(entries) => entries
            .iter()
            .map(|(k, v)| (Step::Key(k.get_ref().as_str()), v))
            .collect(),
        Node::Array(items) => items
            .iter()
            .enumerate()
            .map(|(i, v)| (Step::Index(i), v))
            .collect(),
        _ => return None,
    };
    let mut first: Option<(f64, Hit<'a>)> = None;
    for (step, child) in children {
        path.push((step, child));
        let found = out_of_range(child, path);
        path.pop();
        if let Some(found) = found {
            // Tables keep their keys sorted, not in the text's order.
            if first.as_ref().is_none_or(|f| found.1.offset < f.1.offset) {
                first = Some(found);
            }
        }
    }
    first
}

/// Whether serde refused a key or a value.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Key,
    Value,
}

/// What serde refused: the key or value as written, and the valid ones.
#[derive(Debug, PartialEq)]
struct Refused {
    kind: Kind,
    name: String,
    expected: Vec<String>,
}

impl Refused {
    /// Reads serde's "unknown field `x`, expected one of `a`, `b`" (also
    /// "expected `a`", "expected `a` or `b`", "there are no fields") and
    /// its "unknown variant" twin; `None` for any other message.
    fn from_message(message: &str) -> Option<Self> {
        for (marker, kind) in [
            ("unknown field `", Kind::Key),
            ("unknown variant `", Kind::Value),
        ] {
            if let Some(at) = message.find(marker) {
                let rest = &message[at + marker.len()..];
                let end = rest.find('`')?;
                let expected = rest[end + 1..]
                    .split('`')
                    .skip(1)
                    .step_by(2)
                    .map(String::from)
                    .collect();
                return Some(Self {
                    kind,
                    name: rest[..end].to_string(),
                    expected,
                });
            }
        }
        None
    }

    /// The message, with `place` (" in [[section]] 'box'") after the name.
    fn message(&self, place: &str) -> String {
        let (what, valid) = match self.kind {
            Kind::Key => ("key", "valid keys"),
            Kind::Value => ("value", "valid values"),
        };
        let hint = nearest(&self.name, self.expected.iter().map(String::as_str))
            .map_or_else(String::new, |k| format!("; did you mean `{k}`?"));
        let valid = if self.expected.is_empty() {
            format!("(it takes no {what}s)")
        } else {
            let list: Vec<String> = self.expected.iter().map(|k| format!("`{k}`")).collect();
            format!("({valid}: {})", list.join(", "))
        };
        format!("unknown {what} `{}`{place}{hint} {valid}", self.name)
    }
}

/// A TOML value with the spans of its keys and values; strings (an unknown
/// value is one) and integers (an entry's `id`) are kept, other scalars
/// are not.
enum Node {
    Table(Vec<(Spanned<String>, Spanned<Node>)>),
    Array(Vec<Spanned<Node>>),
    Text(String),
    Integer(i128),
    Float(f64),
    Other,
}

impl<'de> Deserialize<'de> for Node {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NodeVisitor)
    }
}

struct NodeVisitor;

impl<'de> Visitor<'de> for NodeVisitor {
    type Value = Node;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a TOML value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<Node, E> {
        Ok(Node::Other)
    }

    fn visit_i64<E>(self, v: i64) -> Result<Node, E> {
        Ok(Node::Integer(v.into()))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Node, E> {
        Ok(Node::Integer(v.into()))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Node, E> {
        Ok(Node::Float(v))
    }

    fn visit_str<E>(self, s: &str) -> Result<Node, E> {
        Ok(Node::Text(s.to_string()))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Node, A::Error> {
        let mut entries = Vec::new();
        while let Some(key) = map.next_key::<Spanned<String>>()? {
            entries.push((key, map.next_value()?));
        }
        Ok(Node::Table(entries))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Node, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        Ok(Node::Array(items))
    }
}

/// A step from a node to one inside it.
#[derive(Clone, Copy)]
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

/// Where the refused key or value is: its byte offset and the steps from
/// the document to it (the last being the key itself, or the key and
/// indices holding the value), each with the node it reaches.
struct Hit<'a> {
    offset: usize,
    path: Vec<(Step<'a>, &'a Spanned<Node>)>,
}

/// Whether `inner` lies in `outer`.
fn within(inner: &Range<usize>, outer: &Range<usize>) -> bool {
    outer.start <= inner.start && inner.end <= outer.end
}

/// The first key or string value of `refused`'s name, in document order,
/// that lies in `span` or sits directly in the table or array whose span
/// `span` is.
fn find<'a>(
    node: &'a Spanned<Node>,
    refused: &Refused,
    span: &Range<usize>,
    path: &mut Vec<(Step<'a>, &'a Spanned<Node>)>,
) -> Option<Hit<'a>> {
    // serde's span is this table's (or array's): its entries are in it.
    let in_it = node.span() == *span;
    let children: Vec<(Step<'a>, &'a Spanned<Node>, Range<usize>)> = match node.get_ref() {
        Node::Table(entries) => entries
            .iter()
            .map(|(k, v)| (Step::Key(k.get_ref().as_str()), v, k.span()))
            .collect(),
        Node::Array(items) => items
            .iter()
            .enumerate()
            .map(|(i, v)| (Step::Index(i), v, v.span()))
            .collect(),
        Node::Text(_) | Node::Integer(_) | Node::Float(_) | Node::Other => return None,
    };
    for (step, child, key_span) in children {
        let at = match (refused.kind, step, child.get_ref()) {
            (Kind::Key, Step::Key(key), _) if key == refused.name => Some(key_span),
            (Kind::Value, _, Node::Text(text)) if *text == refused.name => Some(child.span()),
            _ => None,
        };
        if let Some(at) = at.filter(|at| in_it || within(at, span)) {
            let mut path = path.clone();
            path.push((step, child));
            return Some(Hit {
                offset: at.start,
                path,
            });
        }
        path.push((step, child));
        let deeper = find(child, refused, span, path);
        path.pop();
        if deeper.is_some() {
            return deeper;
        }
    }
    None
}

impl Hit<'_> {
    /// The place for the message: " in [[section]] 'box'", " in
    /// `dofs[1]` of [interface]", " for `kind` in [[coupling]] 'front'",
    /// " at the top level".
    fn place(&self, kind: Kind) -> String {
        // The value's key (with indices), or the key itself: the tail.
        let tail_start = self
            .path
            .iter()
            .rposition(|(s, _)| matches!(s, Step::Key(_)))
            .unwrap_or(0);
        let (tail, head) = (&self.path[tail_start..], &self.path[..tail_start]);
        let table = table_label(head);
        let inner = render(&head[table.1..]);
        let mut place = String::new();
        if kind == Kind::Value {
            place.push_str(&format!(" for `{}`", render(tail)));
        }
        match (table.0, inner.is_empty()) {
            (None, _) => place.push_str(" at the top level"),
            (Some(t), true) => place.push_str(&format!(" in {t}")),
            (Some(t), false) => place.push_str(&format!(" in `{inner}` of {t}")),
        }
        place
    }
}

/// The top-level table the path starts in ("[interface]", "[[section]]
/// 'box'", "[[element]] id 3", "[[boundary]] number 2") and the number of
/// steps it takes; `None` at the top level.
fn table_label(head: &[(Step<'_>, &Spanned<Node>)]) -> (Option<String>, usize) {
    match head {
        [(Step::Key(t), _), (Step::Index(i), entry), ..]
            if matches!(entry.get_ref(), Node::Table(_)) =>
        {
            (Some(format!("[[{t}]] {}", entry_label(entry, *i))), 2)
        }
        [(Step::Key(t), _), ..] => (Some(format!("[{t}]")), 1),
        _ => (None, 0),
    }
}

/// An entry of an array of tables by its `name`, else its `id`, else its
/// number (from 1).
fn entry_label(entry: &Spanned<Node>, index: usize) -> String {
    let Node::Table(entries) = entry.get_ref() else {
        return format!("number {}", index + 1);
    };
    let value = |key: &str| entries.iter().find(|(k, _)| k.get_ref() == key);
    if let Some((_, v)) = value("name") {
        if let Node::Text(name) = v.get_ref() {
            return format!("'{name}'");
        }
    }
    if let Some((_, v)) = value("id") {
        if let Node::Integer(id) = v.get_ref() {
            return format!("id {id}");
        }
    }
    format!("number {}", index + 1)
}

/// Steps written as a dotted path: `dofs[1].dof`.
fn render(steps: &[(Step<'_>, &Spanned<Node>)]) -> String {
    let mut s = String::new();
    for (step, _) in steps {
        match step {
            Step::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Step::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;
    use std::path::Path;

    #[test]
    fn serde_messages_are_read() {
        let r = |m| Refused::from_message(m).unwrap();
        let field = r("unknown field `wal`, expected one of `radius`, `wall`");
        assert_eq!(field.kind, Kind::Key);
        assert_eq!(field.name, "wal");
        assert_eq!(field.expected, ["radius", "wall"]);
        assert_eq!(r("unknown field `x`, expected `alpha`").expected, ["alpha"]);
        let variant = r("unknown variant `rigd`, expected `rigid` or `distributing`");
        assert_eq!(variant.kind, Kind::Value);
        assert_eq!(variant.expected, ["rigid", "distributing"]);
        assert!(r("unknown field `x`, there are no fields")
            .expected
            .is_empty());
        assert_eq!(Refused::from_message("missing field `name`"), None);
    }

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)] // read to be refused
    struct Doc {
        part: Vec<Part>,
        #[serde(default)]
        settings: Option<Settings>,
    }

    #[derive(Deserialize, Debug)]
    #[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
    #[allow(dead_code)]
    enum Part {
        Rod { name: String, length: f64 },
        Mass { id: u64, mass: f64 },
    }

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Settings {
        axes: Vec<Axis>,
        points: Vec<Point>,
    }

    #[derive(Deserialize, Debug)]
    #[serde(rename_all = "lowercase")]
    enum Axis {
        X,
        Y,
    }

    #[derive(Deserialize, Debug)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Point {
        at: f64,
    }

    const TEXT: &str = "\
[[part]]
type = \"rod\"
name = \"a\"
length = 1.0

[[part]]
type = \"mass\"
id = 7
mass = 2.0

[settings]
axes = [\"x\", \"y\"]
points = [{ at = 1.0 }, { at = 2.0 }]
";

    /// The message for `TEXT` with `from` replaced by `to`.
    fn refused(from: &str, to: &str) -> String {
        assert_eq!(TEXT.matches(from).count(), 1, "{from}");
        let text = TEXT.replace(from, to);
        let src = TomlSource::new(Path::new("t.toml"), &text);
        src.parse::<Doc>().unwrap_err().to_string()
    }

    #[test]
    fn the_variant_text_is_read() {
        let src = TomlSource::new(Path::new("t.toml"), TEXT);
        src.parse::<Doc>().unwrap();
    }

    #[test]
    fn a_key_of_a_tagged_table_is_named_at_its_line_not_the_header() {
        assert_eq!(
            refused("length = 1.0", "lenght = 1.0"),
            "t.toml:4: unknown key `lenght` in [[part]] 'a'; did you mean `length`? \
             (valid keys: `name`, `length`)"
        );
        assert_eq!(
            refused("mass = 2.0", "mas = 2.0"),
            "t.toml:9: unknown key `mas` in [[part]] id 7; did you mean `mass`? \
             (valid keys: `id`, `mass`)"
        );
    }

    #[test]
    fn a_tag_value_is_named_with_its_key() {
        assert_eq!(
            refused("type = \"mass\"", "type = \"mas\""),
            "t.toml:7: unknown value `mas` for `type` in [[part]] id 7; did you mean `mass`? \
             (valid values: `rod`, `mass`)"
        );
    }

    #[test]
    fn keys_and_values_in_inline_tables_and_arrays() {
        assert_eq!(
            refused("{ at = 2.0 }", "{ att = 2.0 }"),
            "t.toml:13: unknown key `att` in `points[1]` of [settings]; did you mean `at`? \
             (valid keys: `at`)"
        );
        assert_eq!(
            refused("[\"x\", \"y\"]", "[\"x\", \"yy\"]"),
            "t.toml:12: unknown value `yy` for `axes[1]` in [settings]; did you mean `y`? \
             (valid values: `x`, `y`)"
        );
        assert_eq!(
            refused("axes =", "axis ="),
            "t.toml:12: unknown key `axis` in [settings]; did you mean `axes`? \
             (valid keys: `axes`, `points`)"
        );
    }

    #[test]
    fn a_key_far_from_any_valid_one_gets_no_suggestion() {
        assert_eq!(
            refused("[settings]", "[colour]"),
            "t.toml:11: unknown key `colour` at the top level (valid keys: `part`, `settings`)"
        );
    }

    #[test]
    fn unknown_top_level_keys_are_refused_with_the_union() {
        let text = "title = \"t\"\n\n[studdy]\nx = 1\n";
        let src = TomlSource::new(Path::new("m.toml"), text);
        assert!(src.refuse_unknown_top_level(&["title", "study"]).is_err());
        assert_eq!(
            src.refuse_unknown_top_level(&["title", "mesh", "study"])
                .unwrap_err()
                .to_string(),
            "m.toml:3: unknown key `studdy` at the top level; did you mean `study`? \
             (valid keys: `title`, `mesh`, `study`)"
        );
        assert!(src.refuse_unknown_top_level(&["title", "studdy"]).is_ok());
    }
}
