//! A newcomer's first hour (issue 30): the README renders as written (item 6: a blank line after
//! the GP row turned the eleven rows after it into raw `|` text), and shell completion offers
//! planner, family and world-kind names rather than file names (item 4).

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

#[test]
fn completion_offers_planner_family_and_kind_names() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrpp"))
        .args(["completions", "bash"])
        .output()
        .unwrap();
    let script = String::from_utf8_lossy(&o.stdout);
    for words in [
        "hstar ca hca whca coevolution nsga3 pibt lacam cbs eecbs psw gp sequential ga exact hbmo de pso orca",
        "grid trees formation continuous",
        "gen-dense gen-staggered-brick-wall gen-var-density gen-var-density3",
        "random circle",
    ] {
        assert!(script.contains(words), "completion lacks `{words}`");
    }
}
