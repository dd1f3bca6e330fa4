//! The documentation: `README.md` and every Markdown page under `docs/` (the book).
//!
//! **Links.** Every relative Markdown link and image (`[text](target)`, `![alt](target)`,
//! and `[label]: target` definitions) outside fenced code blocks and inline code must
//! name a file or folder that exists, relative to the folder of the page that holds it.
//! `http://`, `https://` and `mailto:` targets and pure `#anchor` links are not checked;
//! a `#fragment` is stripped from a file link.
//!
//! **Flags.** Every `lumen` flag the docs mention must exist. The known flags are the
//! `--long` options printed by `lumen --help` and by `lumen SUBCOMMAND --help` for every
//! subcommand of the top-level help's "Commands:" section, plus the hidden test hooks of
//! [`HIDDEN_FLAGS`], each proved to exist by running it followed by `--help`. A token
//! `--[a-z][a-z0-9-]*` (not preceded by a letter, digit, `-` or `_`) in the docs is
//! checked when
//!
//! - its line contains the word `lumen`, or
//! - it is in a fenced `sh`/`bash`/`shell`/`console` block in which some line invokes
//!   `lumen` or `cargo run` (a line ending in `\` is joined with the next),
//!
//! unless that (joined) line invokes another tool ([`OTHER_TOOLS`]: the Bevy peer, mdBook,
//! `cargo clippy`/`fmt`/`doc`, `xvfb-run`, `valgrind`, `git`) or the token is one of
//! cargo's or the test harness's own flags ([`CARGO_FLAGS`]).

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Flags of cargo and of the test harness, which the docs pass next to `lumen` commands.
const CARGO_FLAGS: &[&str] = &[
    "--release",
    "--workspace",
    "--bin",
    "--example",
    "--test",
    "--lib",
    "--all-targets",
    "--no-deps",
    "--features",
    "--package",
    "--test-threads",
    "--nocapture",
    "--ignored",
    "--include-ignored",
    "--exact",
];

/// A line containing one of these invokes another program, whose flags are not Lumen's.
const OTHER_TOOLS: &[&str] = &[
    "bevy-spheres",
    "run.sh",
    "mdbook",
    "cargo clippy",
    "cargo fmt",
    "cargo doc",
    "xvfb-run",
    "valgrind",
    "git ",
    "#SBATCH",
    "parallel -S",
];

/// Fenced blocks in these languages are shell commands.
const SHELL_BLOCKS: &[&str] = &["sh", "bash", "shell", "console"];

/// Flags hidden from `--help` (test hooks) that the docs may mention: subcommand, flag
/// and a valid value. Each is checked by `lumen SUBCOMMAND FLAG VALUE --help`, which
/// prints the help only when clap accepts the flag.
const HIDDEN_FLAGS: &[(&str, &str, &str)] = &[("view", "--lose-device-after", "1")];

fn repo_root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

/// `README.md` and every `.md` file under `docs/`, sorted.
fn markdown_files(root: &Path) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let entries = fs::read_dir(dir).unwrap_or_else(|e| panic!("read {}: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("directory entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let mut files = vec![root.join("README.md")];
    walk(&root.join("docs"), &mut files);
    files.sort();
    files
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()))
}

/// The path of `path` relative to the repository root, for messages.
fn shown(root: &Path, path: &Path) -> String {
    path.strip_prefix(root)
        .unwrap_or(path)
        .display()
        .to_string()
}

/// The info string's first word when `line` opens or closes a fenced code block.
fn fence(line: &str) -> Option<&str> {
    let rest = line.trim_start().strip_prefix("```")?;
    Some(rest.split_whitespace().next().unwrap_or(""))
}

/// `line` with every inline code span replaced by `x`, so that code is not read as links.
fn strip_code_spans(line: &str) -> String {
    let mut out = String::new();
    let mut rest = line;
    while let Some(start) = rest.find('`') {
        out.push_str(&rest[..start]);
        let from = &rest[start..];
        let ticks = from.len() - from.trim_start_matches('`').len();
        let body = &from[ticks..];
        match body.find(&from[..ticks]) {
            Some(end) => {
                out.push('x');
                rest = &body[end + ticks..];
            }
            None => {
                out.push_str(from);
                rest = "";
            }
        }
    }
    out.push_str(rest);
    out
}

/// The link and image targets of a Markdown text, with their 1-based line numbers.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut targets = Vec::new();
    let mut in_fence = false;
    for (index, line) in text.lines().enumerate() {
        if fence(line).is_some() {
            in_fence = !in_fence;
            continue;
        }
        if in_fence {
            continue;
        }
        let line = strip_code_spans(line);
        for (at, _) in line.match_indices("](") {
            let rest = line[at + 2..].trim_start();
            let rest = rest.strip_prefix('<').unwrap_or(rest);
            let end = rest
                .find(|c: char| c == ')' || c == '>' || c.is_whitespace())
                .unwrap_or(rest.len());
            if end > 0 {
                targets.push((index + 1, rest[..end].to_string()));
            }
        }
        // A reference definition: `[label]: target`.
        let trimmed = line.trim_start();
        if let Some(label) = trimmed.strip_prefix('[')
            && let Some(close) = label.find(']')
            && close > 0
            && let Some(def) = label[close + 1..].strip_prefix(':')
            && let Some(target) = def.split_whitespace().next()
        {
            let target = target.trim_start_matches('<').trim_end_matches('>');
            targets.push((index + 1, target.to_string()));
        }
    }
    targets
}

/// Whether a link target is checked as a local path.
fn is_local(target: &str) -> bool {
    !(target.starts_with("http://")
        || target.starts_with("https://")
        || target.starts_with("mailto:")
        || target.starts_with('#'))
}

/// Whether `line` contains `word` between non-word characters.
fn has_word(line: &str, word: &str) -> bool {
    let is_word = |c: char| c.is_alphanumeric() || c == '_';
    line.match_indices(word).any(|(at, _)| {
        let before = line[..at].chars().next_back();
        let after = line[at + word.len()..].chars().next();
        !before.is_some_and(is_word) && !after.is_some_and(is_word)
    })
}

/// Every token `--[a-z][a-z0-9-]*` of `line` not preceded by a letter, digit, `-` or `_`,
/// trailing hyphens removed.
fn flag_tokens(line: &str) -> Vec<String> {
    let b = line.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i + 2 < b.len() {
        let boundary =
            i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'-' || b[i - 1] == b'_');
        if boundary && b[i] == b'-' && b[i + 1] == b'-' && b[i + 2].is_ascii_lowercase() {
            let mut j = i + 3;
            while j < b.len()
                && (b[j].is_ascii_lowercase() || b[j].is_ascii_digit() || b[j] == b'-')
            {
                j += 1;
            }
            tokens.push(line[i..j].trim_end_matches('-').to_string());
            i = j;
        } else {
            i += 1;
        }
    }
    tokens
}

fn invokes_other_tool(line: &str) -> bool {
    OTHER_TOOLS.iter().any(|tool| line.contains(tool))
}

/// The flags a (joined) line contributes, with `line_number`.
fn line_flags(line_number: usize, line: &str, out: &mut Vec<(usize, String)>) {
    if invokes_other_tool(line) {
        return;
    }
    for flag in flag_tokens(line) {
        if !CARGO_FLAGS.contains(&flag.as_str()) {
            out.push((line_number, flag));
        }
    }
}

/// Every `lumen` flag a Markdown text mentions, by the rule of this file's header, with
/// its 1-based line number.
fn doc_flags(text: &str) -> Vec<(usize, String)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut flags = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let Some(info) = fence(lines[i]) else {
            if has_word(lines[i], "lumen") {
                line_flags(i + 1, lines[i], &mut flags);
            }
            i += 1;
            continue;
        };
        let start = i + 1;
        let mut end = start;
        while end < lines.len() && fence(lines[end]).is_none() {
            end += 1;
        }
        let body = &lines[start..end];
        let shell = SHELL_BLOCKS.contains(&info)
            && body
                .iter()
                .any(|l| has_word(l, "lumen") || l.contains("cargo run"));
        let mut k = 0;
        while k < body.len() {
            let first = start + k + 1;
            let mut joined = body[k].to_string();
            while joined.trim_end().ends_with('\\') && k + 1 < body.len() {
                let kept = joined.trim_end().trim_end_matches('\\').to_string();
                k += 1;
                joined = format!("{kept} {}", body[k]);
            }
            if shell || has_word(&joined, "lumen") {
                line_flags(first, &joined, &mut flags);
            }
            k += 1;
        }
        i = end + 1;
    }
    flags
}

/// The flags of `text` (see [`doc_flags`]) that are not in `known`.
fn missing_flags(text: &str, known: &BTreeSet<String>) -> Vec<(usize, String)> {
    doc_flags(text)
        .into_iter()
        .filter(|(_, flag)| !known.contains(flag))
        .collect()
}

fn lumen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lumen"))
        .args(args)
        .env_remove("CLICOLOR_FORCE")
        .env("NO_COLOR", "1")
        .output()
        .expect("lumen runs")
}

fn help(args: &[&str]) -> String {
    let out = lumen(args);
    assert!(
        out.status.success(),
        "lumen {} failed: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The subcommands listed in the "Commands:" section of clap's top-level help, without
/// `help`. A command's line is indented by two spaces; wrapped descriptions, more.
fn subcommands(top_help: &str) -> Vec<String> {
    top_help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect()
}

/// Every flag the `lumen` binary accepts (see the header).
fn known_flags() -> BTreeSet<String> {
    let top = help(&["--help"]);
    let commands = subcommands(&top);
    assert!(
        !commands.is_empty(),
        "no subcommands found in lumen --help:\n{top}"
    );
    let mut texts = vec![top];
    for command in &commands {
        texts.push(help(&[command.as_str(), "--help"]));
    }
    let mut known: BTreeSet<String> = texts.iter().flat_map(|t| flag_tokens(t)).collect();
    for &(command, flag, value) in HIDDEN_FLAGS {
        let out = lumen(&[command, flag, value, "--help"]);
        assert!(
            out.status.success(),
            "hidden flag {flag} of `lumen {command}` is gone: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        known.insert(flag.to_string());
    }
    known
}

#[test]
fn every_relative_link_resolves() {
    let root = repo_root();
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in markdown_files(&root) {
        let dir = file.parent().expect("a file has a folder");
        for (line, target) in link_targets(&read(&file)) {
            if !is_local(&target) {
                continue;
            }
            let path = target.split('#').next().unwrap_or("");
            if path.is_empty() {
                continue;
            }
            checked += 1;
            if !dir.join(path).exists() {
                failures.push(format!("{}:{line}: {target}", shown(&root, &file)));
            }
        }
    }
    assert!(checked > 0, "no relative links found: is the book there?");
    assert!(
        failures.is_empty(),
        "{} broken relative link(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn every_documented_lumen_flag_exists() {
    let root = repo_root();
    let known = known_flags();
    let mut failures = Vec::new();
    let mut checked = 0;
    for file in markdown_files(&root) {
        let text = read(&file);
        checked += doc_flags(&text).len();
        for (line, flag) in missing_flags(&text, &known) {
            failures.push(format!("{}:{line}: {flag}", shown(&root, &file)));
        }
    }
    assert!(checked > 0, "no lumen flags found in the docs");
    assert!(
        failures.is_empty(),
        "{} flag(s) in the docs that no `lumen --help` lists:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn a_made_up_flag_is_reported() {
    let known: BTreeSet<String> = ["--size", "--explain"].map(String::from).into();
    let text = "Render it:\n\n    lumen render spheres --size 256x256 --explain\n\n\
                `lumen render spheres --no-such-flag` does not exist.\n";
    assert_eq!(
        missing_flags(text, &known),
        vec![(5, "--no-such-flag".to_string())]
    );
}

#[test]
fn shell_blocks_are_checked_and_other_tools_are_not() {
    let known: BTreeSet<String> = ["--json", "--headless"].map(String::from).into();
    let text = "```sh\n\
                cargo run --release -- --headless\n\
                cd bevy-spheres && ./run.sh --deferred\n\
                lumen bench spheres \\\n    --json out.json --bogus\n\
                mdbook build docs --dest-dir out\n\
                ```\n\
                Not a command: --free-text, and cargo test --workspace -- --test-threads 4.\n\
                ```text\n--inside-text-block\n```\n";
    assert_eq!(
        missing_flags(text, &known),
        vec![(4, "--bogus".to_string())]
    );
}

#[test]
fn flag_tokens_need_a_boundary() {
    assert_eq!(
        flag_tokens("a--b x --dof-rings 3 | --- | `--no-dof`, --vignette-"),
        vec!["--dof-rings", "--no-dof", "--vignette"]
    );
    assert!(has_word("`lumen render`", "lumen"));
    assert!(has_word("lumen: unknown scene", "lumen"));
    assert!(!has_word("lumen_game::view", "lumen"));
    assert!(!has_word("Lumen renders", "lumen"));
}

#[test]
fn links_images_and_definitions_are_found() {
    let text = "See [a](a.md#x), ![img](../i.png \"title\") and <https://x.y>.\n\
                `[not](code.md)` [web](https://example.com) [top](#top)\n\
                ```\n[fenced](no.md)\n```\n\
                [label]: ../defined.md\n";
    let targets = link_targets(text);
    let expect: [(usize, &str); 5] = [
        (1, "a.md#x"),
        (1, "../i.png"),
        (2, "https://example.com"),
        (2, "#top"),
        (6, "../defined.md"),
    ];
    let expect: Vec<(usize, String)> = expect.iter().map(|&(l, t)| (l, t.to_string())).collect();
    assert_eq!(targets, expect);
    let local: Vec<&str> = targets
        .iter()
        .map(|(_, t)| t.as_str())
        .filter(|t| is_local(t))
        .collect();
    assert_eq!(local, vec!["a.md#x", "../i.png", "../defined.md"]);
}

#[test]
fn subcommands_come_from_the_commands_section() {
    let top = "Usage: lumen [OPTIONS] [COMMAND]\n\nCommands:\n  render  Render one frame\n  view    Open the viewer, a description\n          wrapped onto a second line\n  help    Print this message\n\nOptions:\n      --headless  Render to a file\n";
    assert_eq!(subcommands(top), vec!["render", "view"]);
}
