//! Markdown tables.

/// A markdown table built row by row.
#[derive(Clone, Debug, Default)]
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column headers.
    pub fn new<S: AsRef<str>>(header: impl IntoIterator<Item = S>) -> Self {
        Table {
            header: header.into_iter().map(|s| s.as_ref().to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row (missing cells are left empty).
    pub fn row(&mut self, cells: Vec<String>) -> &mut Self {
        self.rows.push(cells);
        self
    }

    /// The table as GitHub-flavoured markdown.
    pub fn render(&self) -> String {
        let n = self.header.len();
        let line = |cells: &[String]| {
            let mut s = String::from("|");
            for k in 0..n {
                // A bare "|" inside a cell (e.g. "|ΔE|") would split the column.
                let cell = cells.get(k).map_or("", String::as_str).replace('|', "\\|");
                s += &format!(" {cell} |");
            }
            s + "\n"
        };
        let mut out = line(&self.header);
        out += &format!("|{}\n", "---|".repeat(n));
        for r in &self.rows {
            out += &line(r);
        }
        out + "\n"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_header_rule_and_rows() {
        let mut t = Table::new(["a", "b"]);
        t.row(vec!["1".into()]);
        assert_eq!(t.render(), "| a | b |\n|---|---|\n| 1 |  |\n\n");
        let mut t = Table::new(["max |ΔE|/E"]);
        t.row(vec!["1 %".into()]);
        assert_eq!(t.render(), "| max \\|ΔE\\|/E |\n|---|\n| 1 % |\n\n");
    }
}
