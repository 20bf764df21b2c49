//! The HTML report's smallest pieces, shared by every section: escaped text, numbers as the
//! report shows them, and table cells that keep their exact value.

/// `s` escaped for HTML text and attributes.
pub(super) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A number as the report shows it: four decimals, or three significant digits in e-notation.
pub(crate) fn num(v: f64) -> String {
    if v.is_infinite() {
        "∞".into()
    } else if v.is_nan() {
        "–".into()
    } else if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e5) {
        format!("{v:.3e}")
    } else {
        format!("{}", (v * 1e4).round() / 1e4)
    }
}

/// A table cell with its exact value in `data-value`.
pub(super) fn cell(key: &str, v: f64) -> String {
    format!("<td data-key=\"{key}\" data-value=\"{v}\">{}</td>", num(v))
}
