//! The README renders as written: its command table is one table (issue 30, item 6: a blank
//! line after the GP row turned the eleven rows after it into raw `|` text).

use std::path::PathBuf;

#[test]
fn the_readme_command_table_is_one_unbroken_table() {
    let readme =
        std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../README.md"))
            .unwrap();
    let lines: Vec<&str> = readme.lines().collect();
    let header = lines
        .iter()
        .position(|l| l.starts_with("| command |"))
        .expect("the README has its command table");
    // Rows run from the header to the first line that is not a row; after it, no line of the
    // section may look like a stray row.
    let end = (header..lines.len())
        .find(|&i| !lines[i].starts_with('|'))
        .unwrap_or(lines.len());
    let section_end = (end..lines.len())
        .find(|&i| lines[i].starts_with("## "))
        .unwrap_or(lines.len());
    let stray: Vec<&str> = lines[end..section_end]
        .iter()
        .copied()
        .filter(|l| l.starts_with("| `mrpp"))
        .collect();
    assert!(stray.is_empty(), "rows cut off from the table: {stray:?}");
    // Every row has the header's two columns (`\|` inside a cell is not a separator).
    for row in &lines[header..end] {
        let separators = row.replace("\\|", "").matches('|').count();
        assert_eq!(separators, 3, "not a two-column row: {row}");
    }
    assert!(end - header > 20, "the table has all its commands");
}
