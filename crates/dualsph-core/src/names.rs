//! Short names of Rust types, for messages and listings.

/// `dualsph_core::components::Position<glam::DVec2>` → `Position<DVec2>`.
pub fn short_type_name(full: &str) -> String {
    let mut out = String::new();
    let mut token = String::new();
    for ch in full.chars() {
        if ch.is_alphanumeric() || ch == '_' || ch == ':' {
            token.push(ch);
        } else {
            out.push_str(token.rsplit("::").next().unwrap_or(""));
            token.clear();
            out.push(ch);
        }
    }
    out.push_str(token.rsplit("::").next().unwrap_or(""));
    out
}
