//! The lines of a text file, as the flatland, OBJ and MTL parsers read them.
//!
//! Files come from every platform, so a line ends at `\n` (Unix), `\r\n` (Windows) or a
//! lone `\r` (classic Mac OS, some exporters), and a UTF-8 byte-order mark (U+FEFF,
//! written by Windows editors) before the first line is skipped. `str::lines` knows
//! only the first two: a CR-only file would be one line, and a byte-order mark would
//! make the first keyword unknown (`unknown keyword '\u{feff}mat'`).

/// The UTF-8 byte-order mark.
const BOM: char = '\u{feff}';

/// The lines of `text`, each with its 1-based number (saturating at `u32::MAX`).
///
/// A line ends at `\n`, `\r\n` or a lone `\r`; the terminator is not part of the line,
/// and a final terminator does not start an empty line. A byte-order mark at the very
/// start is skipped; anywhere else it is ordinary text.
#[must_use]
pub(crate) fn lines(text: &str) -> Lines<'_> {
    Lines {
        rest: text.strip_prefix(BOM).unwrap_or(text),
        number: 0,
    }
}

/// The iterator of [`lines`].
#[derive(Debug, Clone)]
pub(crate) struct Lines<'a> {
    /// The text not yet read.
    rest: &'a str,
    /// The number of the last line returned.
    number: u32,
}

impl<'a> Iterator for Lines<'a> {
    type Item = (u32, &'a str);

    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        // Split at the first line break; `\r\n` is one break, two bytes long
        let (line, rest) = match self.rest.find(['\n', '\r']) {
            Some(at) => {
                let after = &self.rest[at..];
                let skip = if after.starts_with("\r\n") { 2 } else { 1 };
                (&self.rest[..at], &after[skip..])
            }
            None => (self.rest, ""),
        };
        self.rest = rest;
        self.number = self.number.saturating_add(1);
        Some((self.number, line))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec::Vec;

    fn all(text: &str) -> Vec<(u32, &str)> {
        lines(text).collect()
    }

    #[test]
    fn every_line_end_splits() {
        let expected = [(1, "a"), (2, "b"), (3, "c")];
        assert_eq!(all("a\nb\nc\n"), expected);
        assert_eq!(all("a\r\nb\r\nc\r\n"), expected);
        assert_eq!(all("a\rb\rc\r"), expected);
        assert_eq!(all("a\rb\r\nc"), expected);
        assert_eq!(all("a\nb\rc"), expected);
    }

    #[test]
    fn empty_lines_keep_their_numbers() {
        assert_eq!(all("a\r\rb"), [(1, "a"), (2, ""), (3, "b")]);
        assert_eq!(all("a\n\r\nb"), [(1, "a"), (2, ""), (3, "b")]);
        // `\n\r` is two breaks, not one
        assert_eq!(all("a\n\rb"), [(1, "a"), (2, ""), (3, "b")]);
        assert_eq!(all(""), []);
        assert_eq!(all("\n"), [(1, "")]);
        assert_eq!(all("\r\n\r\n"), [(1, ""), (2, "")]);
    }

    #[test]
    fn the_byte_order_mark_is_skipped_at_the_start_only() {
        assert_eq!(all("\u{feff}a\nb"), [(1, "a"), (2, "b")]);
        assert_eq!(all("\u{feff}"), []);
        assert_eq!(all("\u{feff}\r\nb"), [(1, ""), (2, "b")]);
        assert_eq!(all("a\n\u{feff}b"), [(1, "a"), (2, "\u{feff}b")]);
    }
}
