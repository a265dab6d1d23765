//! A minimal streaming JSON writer: one object at a time, no allocation.
//!
//! Floats are written in Rust's shortest round-trip form (`{:?}`), so a reader gets back the
//! very `f64` that was computed; a non-finite value (which the core never produces) is
//! written as `null`, keeping the output valid JSON. Keys and strings are escaped as JSON
//! requires (RFC 8259 §7).

use core::fmt::{self, Write};

/// A streaming JSON object writer over any [`fmt::Write`].
#[derive(Debug)]
pub struct JsonObject<'w, W: Write> {
    out: &'w mut W,
    first: bool,
}

impl<'w, W: Write> JsonObject<'w, W> {
    /// Starts an object: writes `{`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn new(out: &'w mut W) -> Result<Self, fmt::Error> {
        out.write_char('{')?;
        Ok(Self { out, first: true })
    }

    fn key(&mut self, key: &str) -> fmt::Result {
        if !self.first {
            self.out.write_char(',')?;
        }
        self.first = false;
        write_json_string(self.out, key)?;
        self.out.write_char(':')
    }

    /// Writes `"key":number` (`null` if not finite).
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn number(&mut self, key: &str, v: f64) -> fmt::Result {
        self.key(key)?;
        write_number(self.out, v)
    }

    /// Writes `"key":integer`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn integer(&mut self, key: &str, v: u64) -> fmt::Result {
        self.key(key)?;
        write!(self.out, "{v}")
    }

    /// Writes `"key":null` (a value that is undefined, not zero).
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn null(&mut self, key: &str) -> fmt::Result {
        self.key(key)?;
        self.out.write_str("null")
    }

    /// Writes `"key":true|false`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn boolean(&mut self, key: &str, v: bool) -> fmt::Result {
        self.key(key)?;
        self.out.write_str(if v { "true" } else { "false" })
    }

    /// Writes `"key":"escaped string"`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn string(&mut self, key: &str, v: &str) -> fmt::Result {
        self.key(key)?;
        write_json_string(self.out, v)
    }

    /// Writes `"key":[n, n, …]` (each `null` if not finite).
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn numbers(&mut self, key: &str, values: &[f64]) -> fmt::Result {
        self.key(key)?;
        self.out.write_char('[')?;
        for (k, &v) in values.iter().enumerate() {
            if k > 0 {
                self.out.write_char(',')?;
            }
            write_number(self.out, v)?;
        }
        self.out.write_char(']')
    }

    /// Writes `"key":[n, n, …]` of integers.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn integers(&mut self, key: &str, values: impl IntoIterator<Item = u64>) -> fmt::Result {
        self.key(key)?;
        self.out.write_char('[')?;
        for (k, v) in values.into_iter().enumerate() {
            if k > 0 {
                self.out.write_char(',')?;
            }
            write!(self.out, "{v}")?;
        }
        self.out.write_char(']')
    }

    /// Writes `"key":["…", "…"]`: each item's `Display` form as an escaped string.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn displays<T: fmt::Display>(
        &mut self,
        key: &str,
        items: impl IntoIterator<Item = T>,
    ) -> fmt::Result {
        self.key(key)?;
        self.out.write_char('[')?;
        for (k, item) in items.into_iter().enumerate() {
            if k > 0 {
                self.out.write_char(',')?;
            }
            self.out.write_char('"')?;
            write!(JsonEscaped(&mut *self.out), "{item}")?;
            self.out.write_char('"')?;
        }
        self.out.write_char(']')
    }

    /// Writes `"key":` followed by a nested object filled by `fill`.
    ///
    /// # Errors
    /// Whatever the underlying writer or `fill` returns.
    pub fn object(
        &mut self,
        key: &str,
        fill: impl FnOnce(&mut JsonObject<'_, W>) -> fmt::Result,
    ) -> fmt::Result {
        self.key(key)?;
        let mut inner = JsonObject::new(self.out)?;
        fill(&mut inner)?;
        inner.finish()
    }

    /// Ends the object: writes `}`.
    ///
    /// # Errors
    /// Whatever the underlying writer returns.
    pub fn finish(self) -> fmt::Result {
        self.out.write_char('}')
    }
}

/// A finite `v` in its shortest round-trip form, else `null`.
fn write_number<W: Write>(out: &mut W, v: f64) -> fmt::Result {
    if v.is_finite() {
        write!(out, "{v:?}")
    } else {
        out.write_str("null")
    }
}

/// `s` as a JSON string: quotes, backslash, `\n`, `\r`, `\t` by their short escapes, other
/// control characters as `\u00XX`.
fn write_json_string<W: Write>(out: &mut W, s: &str) -> fmt::Result {
    out.write_char('"')?;
    for c in s.chars() {
        match c {
            '"' => out.write_str("\\\"")?,
            '\\' => out.write_str("\\\\")?,
            '\n' => out.write_str("\\n")?,
            '\r' => out.write_str("\\r")?,
            '\t' => out.write_str("\\t")?,
            c if (c as u32) < 0x20 => write!(out, "\\u{:04x}", c as u32)?,
            c => out.write_char(c)?,
        }
    }
    out.write_char('"')
}

/// A `fmt::Write` adapter that escapes what it writes as the inside of a JSON string (every
/// control character as `\u00XX`: the bytes [`JsonObject::displays`] has always written).
struct JsonEscaped<'a, W: Write>(&'a mut W);

impl<W: Write> Write for JsonEscaped<'_, W> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for c in s.chars() {
            match c {
                '"' => self.0.write_str("\\\"")?,
                '\\' => self.0.write_str("\\\\")?,
                c if (c as u32) < 0x20 => write!(self.0, "\\u{:04x}", c as u32)?,
                c => self.0.write_char(c)?,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_escapes_and_nulls() {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s).unwrap();
        o.string("a\"b", "x\ny").unwrap();
        o.number("nan", f64::NAN).unwrap();
        o.number("one", 1.0).unwrap();
        o.numbers("list", &[0.5, f64::INFINITY]).unwrap();
        o.displays("notes", ["tab\there"]).unwrap();
        o.finish().unwrap();
        assert_eq!(
            s,
            r#"{"a\"b":"x\ny","nan":null,"one":1.0,"list":[0.5,null],"notes":["tab\u0009here"]}"#
        );
    }
}
