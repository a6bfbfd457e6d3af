//! Hostile text for parser property tests, shared by the `mc`, `fit` and `gpu` test suites:
//! random mutations of a valid file and fully random strings.
//!
//! A mutation flips a byte, truncates, deletes, duplicates or inserts a line, or replaces one
//! number of the file by a value chosen to break naive parsers: NaN, ±inf, −1, 0, 1e308, counts
//! such as 10¹⁵ that abort on allocation, values beyond `u64`, empty strings and unicode.

use proptest::prelude::*;
use proptest::sample::Index;

/// Values a hostile or careless user writes where a number belongs.
pub const HOSTILE_NUMBERS: &[&str] = &[
    "NaN",
    "nan",
    "inf",
    "-inf",
    "-1",
    "0",
    "-0",
    "1e308",
    "-1e308",
    "1e-320",
    "1e15",
    "1000000000000000",
    "18446744073709551616",
    "99999999999999999999999999999999999999",
    "0.5",
    "1e400",
    "",
    "\"\"",
    "é",
    "🦀",
    "0x10",
    "1_0",
    "+",
    "-",
    ".",
    "1e",
];

/// One edit of a text.
#[derive(Clone, Debug)]
pub enum Mutation {
    /// XOR one byte (the result is read back lossily as UTF-8, as a file reader would refuse or
    /// replace invalid sequences).
    FlipByte(Index, u8),
    /// Cut the text at a byte.
    Truncate(Index),
    /// Remove a line.
    DeleteLine(Index),
    /// Repeat a line.
    DuplicateLine(Index),
    /// Insert an arbitrary line.
    InsertLine(Index, String),
    /// Replace one numeric token by a hostile value.
    ReplaceNumber(Index, &'static str),
}

impl Mutation {
    /// The text after this edit.
    pub fn apply(&self, text: &str) -> String {
        let mut lines: Vec<&str> = text.split('\n').collect();
        match self {
            Mutation::FlipByte(i, x) => {
                let mut b = text.as_bytes().to_vec();
                if !b.is_empty() {
                    let k = i.index(b.len());
                    b[k] ^= (*x).max(1);
                }
                String::from_utf8_lossy(&b).into_owned()
            }
            Mutation::Truncate(i) => {
                let b = text.as_bytes();
                String::from_utf8_lossy(&b[..i.index(b.len() + 1)]).into_owned()
            }
            Mutation::DeleteLine(i) => {
                lines.remove(i.index(lines.len()));
                lines.join("\n")
            }
            Mutation::DuplicateLine(i) => {
                let k = i.index(lines.len());
                lines.insert(k, lines[k]);
                lines.join("\n")
            }
            Mutation::InsertLine(i, s) => {
                lines.insert(i.index(lines.len() + 1), s);
                lines.join("\n")
            }
            Mutation::ReplaceNumber(i, v) => {
                let spans = numbers(text);
                if spans.is_empty() {
                    return text.to_string();
                }
                let (a, b) = spans[i.index(spans.len())];
                format!("{}{v}{}", &text[..a], &text[b..])
            }
        }
    }
}

/// Byte spans of the numeric tokens of `text` (a digit, with signs, dots, exponents and `_`).
pub fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let part = |c: u8| c.is_ascii_digit() || matches!(c, b'.' | b'e' | b'E' | b'+' | b'-' | b'_');
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = (b[i].is_ascii_digit() || matches!(b[i], b'-' | b'+' | b'.'))
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'));
        if starts {
            let mut j = i;
            while j < b.len() && part(b[j]) {
                j += 1;
            }
            if b[i..j].iter().any(u8::is_ascii_digit) {
                spans.push((i, j));
                i = j;
                continue;
            }
        }
        i += 1;
    }
    spans
}

/// A line a user could paste anywhere: printable ASCII, unicode, or a hostile number.
fn any_line() -> impl Strategy<Value = String> {
    prop_oneof![
        "[ -~]{0,40}",
        any::<String>(),
        prop::sample::select(HOSTILE_NUMBERS).prop_map(str::to_string),
    ]
}

/// One random edit.
pub fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        1 => (any::<Index>(), any::<u8>()).prop_map(|(i, x)| Mutation::FlipByte(i, x)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
        1 => any::<Index>().prop_map(Mutation::DeleteLine),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
        1 => (any::<Index>(), any_line()).prop_map(|(i, s)| Mutation::InsertLine(i, s)),
        4 => (any::<Index>(), prop::sample::select(HOSTILE_NUMBERS))
            .prop_map(|(i, v)| Mutation::ReplaceNumber(i, v)),
    ]
}

/// `valid` after one to four random edits.
pub fn mutated(valid: &'static str) -> impl Strategy<Value = String> {
    prop::collection::vec(mutation(), 1..=4).prop_map(move |edits| {
        edits
            .iter()
            .fold(valid.to_string(), |text, m| m.apply(&text))
    })
}

/// Fully random text: arbitrary unicode, or lines of printable ASCII and numbers.
pub fn random_text() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<String>(),
        prop::collection::vec(any_line(), 0..12).prop_map(|l| l.join("\n")),
    ]
}

/// Every way `valid` can be a hostile input: mutations (mostly) or random text.
pub fn hostile(valid: &'static str) -> impl Strategy<Value = String> {
    prop_oneof![4 => mutated(valid), 1 => random_text()]
}
