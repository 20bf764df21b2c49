//! The HTML report's smallest pieces, shared by every section: escaped text, numbers as the
//! report shows them, and table cells that keep their exact value.

/// `s` escaped for HTML text and attributes.
pub(super) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

pub(crate) use crate::output::num;

/// A table cell with its exact value in `data-value`.
pub(super) fn cell(key: &str, v: f64) -> String {
    format!("<td data-key=\"{key}\" data-value=\"{v}\">{}</td>", num(v))
}
