//! Numbers as messages show them. An accepted or refused value is echoed to the user in
//! errors and warnings of every crate: `1e300` must not become 301 digits, nor `3.4e38` a
//! 39-digit integer.

use std::fmt;

/// `value` for a message: at most six significant digits; plain below 10⁶ and from 10⁻⁴
/// on (`0.35`, `1500`), scientific outside (`1e300`, `3.40282e38`, `1e-46`); `NaN`, `inf`
/// and `-inf` by name.
pub fn readable(value: impl Into<f64>) -> Readable {
    Readable(value.into())
}

/// A finite number read from `text` (surrounding white space ignored); the error says why
/// not, without the value (the caller's message shows it, shortened).
pub fn finite_number(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        Ok(_) => Err("is not finite".to_owned()),
        Err(_) => Err("is not a number".to_owned()),
    }
}

/// `text` for a message: at most 40 characters, the rest elided with the count (a
/// hostile or careless value of megabytes is not echoed whole), control characters
/// written as escapes (`\n`, `\u{1b}`: a message stays one line, and a terminal shows
/// the value rather than obeying it).
pub fn shortened(text: &str) -> String {
    match text.char_indices().nth(40) {
        Some((cut, _)) => format!(
            "{}… ({} characters)",
            escaped(&text[..cut]),
            text.chars().count()
        ),
        None => escaped(text),
    }
}

/// `text` whole (a path: messages show paths whole), its control characters written as
/// escapes (`\n`, `\u{1b}`) as [`shortened`] writes them.
pub fn escaped(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// A number shown as [`readable`] describes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Readable(pub f64);

impl fmt::Display for Readable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if !x.is_finite() || x == 0.0 {
            return write!(f, "{x}");
        }
        // Six significant digits, as the exponent form gives them; the value rounded so.
        let scientific = format!("{x:.5e}");
        let (mantissa, exponent) = scientific
            .split_once('e')
            .expect("the e format has an exponent");
        let exponent: i32 = exponent.parse().expect("the exponent is an integer");
        if (-4..6).contains(&exponent) {
            let rounded: f64 = scientific.parse().expect("the e format parses back");
            write!(f, "{rounded}")
        } else {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            write!(f, "{mantissa}e{exponent}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::readable;

    #[test]
    fn numbers_are_short_and_exact_where_they_are_short() {
        for (value, shown) in [
            (0.0, "0"),
            (-0.0, "-0"),
            (1.0, "1"),
            (0.35, "0.35"),
            (1500.0, "1500"),
            (-2.5, "-2.5"),
            (1e-4, "0.0001"),
            (999_999.0, "999999"),
            (1e6, "1e6"),
            (1_234_567.0, "1.23457e6"),
            (9_999_999.0, "1e7"),
            (1e300, "1e300"),
            (f64::from(f32::MAX), "3.40282e38"),
            (1e-46, "1e-46"),
            (0.1 + 0.2, "0.3"),
            (123.456_789, "123.457"),
            (-1.5e-300, "-1.5e-300"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(readable(value).to_string(), shown, "{value:e}");
        }
        assert_eq!(readable(0.35f32).to_string(), "0.35");
    }

    #[test]
    fn long_text_is_cut_with_its_length() {
        assert_eq!(super::shortened("short"), "short");
        // Control characters as escapes: one line, nothing a terminal acts on.
        assert_eq!(super::shortened("a\nb\u{1b}[2J\tc"), "a\\nb\\u{1b}[2J\\tc");
        let long = "é".repeat(10_000);
        assert_eq!(
            super::shortened(&long),
            format!("{}… (10000 characters)", "é".repeat(40))
        );
    }
}
