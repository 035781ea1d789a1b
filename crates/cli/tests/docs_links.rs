//! Every relative link in the documentation resolves: `README.md`,
//! `CHANGELOG.md` and every Markdown file under `docs/` (and the READMEs of
//! `deploy/` and `scenes/external/`, which they link to) name files and
//! directories that exist, and a link with an `#anchor` into a Markdown file
//! names one of its headings, slugged as GitHub slugs them (lower case,
//! punctuation dropped, spaces to hyphens, `-1`, `-2`, … for repeats).
//! Links to `http(s)` and `mailto` addresses are not followed.
//!
//! The Markdown read here is the subset the documentation uses: ATX and
//! setext headings, inline links and images `[text](target "title")`,
//! reference definitions `[label]: target`, fenced code blocks and code
//! spans (whose contents are not links).

use std::collections::{HashMap, HashSet};
use std::fs;
use std::path::{Component, Path, PathBuf};

/// The repository's root (this crate is `crates/cli`).
fn repository_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .expect("the repository root exists")
}

/// Every `.md` file under `directory`, recursively, in a stable order.
fn markdown_files_under(directory: &Path, files: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = fs::read_dir(directory)
        .unwrap_or_else(|error| panic!("cannot read {}: {error}", directory.display()))
        .map(|entry| entry.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            markdown_files_under(&path, files);
        } else if path.extension().is_some_and(|extension| extension == "md") {
            files.push(path);
        }
    }
}

/// The documentation files whose links are checked.
fn documentation_files(root: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = ["README.md", "CHANGELOG.md"]
        .iter()
        .map(|name| root.join(name))
        .collect();
    markdown_files_under(&root.join("docs"), &mut files);
    for optional in ["deploy/README.md", "scenes/external/README.md"] {
        let path = root.join(optional);
        if path.is_file() {
            files.push(path);
        }
    }
    files
}

/// A line of a Markdown file outside fenced code blocks, with its number.
struct TextLine<'a> {
    number: usize,
    text: &'a str,
}

/// Whether `line` opens or closes a fenced code block (three or more
/// backticks or tildes, indented or not: fences in list items count).
fn is_fence(line: &str) -> bool {
    let rest = line.trim_start();
    rest.starts_with("```") || rest.starts_with("~~~")
}

/// The lines of `text` outside fenced code blocks; a blank line stands
/// where a fenced block was, so that it separates paragraphs.
fn lines_outside_code(text: &str) -> Vec<TextLine<'_>> {
    let mut lines = Vec::new();
    let mut in_fence = false;
    for (index, line) in text.lines().enumerate() {
        if is_fence(line) {
            in_fence = !in_fence;
            lines.push(TextLine {
                number: index + 1,
                text: "",
            });
        } else if !in_fence {
            lines.push(TextLine {
                number: index + 1,
                text: line,
            });
        }
    }
    lines
}

/// `text` with its code spans blanked out (a run of n backticks up to the
/// next run of exactly n backticks), byte for byte.
fn without_code_spans(text: &str) -> String {
    let characters: Vec<char> = text.chars().collect();
    let mut result = String::with_capacity(text.len());
    let mut index = 0;
    while index < characters.len() {
        if characters[index] != '`' {
            result.push(characters[index]);
            index += 1;
            continue;
        }
        let run_start = index;
        while index < characters.len() && characters[index] == '`' {
            index += 1;
        }
        let run = index - run_start;
        // Look for the closing run of the same length.
        let mut search = index;
        let mut closing = None;
        while search < characters.len() {
            if characters[search] == '`' {
                let start = search;
                while search < characters.len() && characters[search] == '`' {
                    search += 1;
                }
                if search - start == run {
                    closing = Some(search);
                    break;
                }
            } else {
                search += 1;
            }
        }
        match closing {
            Some(end) => {
                // As many spaces as the span has bytes, so that byte offsets
                // into the result are offsets into `text`.
                let bytes: usize = characters[run_start..end]
                    .iter()
                    .map(|c| c.len_utf8())
                    .sum();
                result.extend(std::iter::repeat_n(' ', bytes));
                index = end;
            }
            None => result.extend(std::iter::repeat_n('`', run)),
        }
    }
    result
}

/// The text of an ATX heading line (`# Title #`), if it is one.
fn atx_heading(line: &str) -> Option<&str> {
    let indentation = line.len() - line.trim_start_matches(' ').len();
    if indentation > 3 {
        return None;
    }
    let rest = line.trim_start_matches(' ');
    let level = rest.len() - rest.trim_start_matches('#').len();
    if !(1..=6).contains(&level) {
        return None;
    }
    let after = &rest[level..];
    if !(after.is_empty() || after.starts_with(' ') || after.starts_with('\t')) {
        return None;
    }
    let title = after.trim();
    // A closing sequence of #s preceded by a space is not part of the title.
    let without_closing = title.trim_end_matches('#');
    let title = if without_closing.is_empty() || without_closing.ends_with(' ') {
        without_closing.trim_end()
    } else {
        title
    };
    Some(title)
}

/// Whether `line` underlines the line before it as a setext heading.
fn is_setext_underline(line: &str) -> bool {
    let trimmed = line.trim();
    let indentation = line.len() - line.trim_start_matches(' ').len();
    indentation <= 3
        && !trimmed.is_empty()
        && (trimmed.chars().all(|c| c == '=') || trimmed.chars().all(|c| c == '-'))
}

/// The text GitHub shows for a heading's Markdown: code spans lose their
/// backticks, links and images keep their text.
fn heading_text(markdown: &str) -> String {
    let mut text = markdown.replace('`', "");
    // [text](target) and ![text](target) → text.
    while let Some(middle) = text.find("](") {
        let Some(open) = text[..middle].rfind('[') else {
            break;
        };
        let Some(close) = text[middle..].find(')').map(|offset| middle + offset) else {
            break;
        };
        let label = text[open + 1..middle].to_string();
        let start = if open > 0 && text[..open].ends_with('!') {
            open - 1
        } else {
            open
        };
        text.replace_range(start..=close, &label);
    }
    text
}

/// GitHub's anchor for a heading's text.
fn slug(text: &str) -> String {
    text.trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The anchors of a Markdown file: its headings' slugs (repeats numbered
/// as GitHub numbers them) and the `id`/`name` attributes of HTML anchors.
fn anchors(text: &str) -> HashSet<String> {
    let mut anchors = HashSet::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut add_heading = |title: &str, anchors: &mut HashSet<String>| {
        let base = slug(&heading_text(title));
        let count = seen.entry(base.clone()).or_insert(0);
        let anchor = if *count == 0 {
            base.clone()
        } else {
            format!("{base}-{count}")
        };
        *count += 1;
        anchors.insert(anchor);
    };
    let lines = lines_outside_code(text);
    for (index, line) in lines.iter().enumerate() {
        if let Some(title) = atx_heading(line.text) {
            add_heading(title, &mut anchors);
        } else if index + 1 < lines.len()
            && lines[index + 1].number == line.number + 1
            && is_setext_underline(lines[index + 1].text)
            && !line.text.trim().is_empty()
            && !line.text.trim_start().starts_with('|')
            && atx_heading(line.text).is_none()
            && (index == 0 || lines[index - 1].text.trim().is_empty())
        {
            add_heading(line.text.trim(), &mut anchors);
        }
        for attribute in ["id=\"", "name=\""] {
            let mut rest = line.text;
            while let Some(position) = rest.find(attribute) {
                rest = &rest[position + attribute.len()..];
                if let Some(end) = rest.find('"') {
                    anchors.insert(rest[..end].to_string());
                }
            }
        }
    }
    anchors
}

/// A link found in a file: its line and its target as written.
struct Link {
    line: usize,
    target: String,
}

/// The destination of an inline link whose `(` is at the start of `rest`
/// (without the parenthesis): up to the closing `)` or the title.
fn destination(rest: &str) -> Option<String> {
    let rest = rest.trim_start();
    if let Some(inner) = rest.strip_prefix('<') {
        return inner.find('>').map(|end| inner[..end].to_string());
    }
    let mut depth = 0usize;
    let mut end = None;
    for (position, c) in rest.char_indices() {
        match c {
            '(' => depth += 1,
            ')' if depth == 0 => {
                end = Some(position);
                break;
            }
            ')' => depth -= 1,
            c if c.is_whitespace() => {
                end = Some(position);
                break;
            }
            _ => {}
        }
    }
    end.map(|end| rest[..end].to_string())
}

/// The links of a Markdown file: inline links and images, and reference
/// definitions, outside code.
fn links(text: &str) -> Vec<Link> {
    let mut links = Vec::new();
    // Paragraphs: runs of non-blank lines, so that code spans and links
    // may wrap across lines.
    let lines = lines_outside_code(text);
    let mut paragraph: Vec<&TextLine> = Vec::new();
    let flush = |paragraph: &mut Vec<&TextLine>, links: &mut Vec<Link>| {
        if paragraph.is_empty() {
            return;
        }
        // Each line's start in the joined text, to report line numbers.
        let mut joined = String::new();
        let mut starts = Vec::new();
        for line in paragraph.iter() {
            starts.push((joined.len(), line.number));
            joined.push_str(line.text);
            joined.push(' ');
        }
        let clean = without_code_spans(&joined);
        let line_at = |offset: usize| {
            starts
                .iter()
                .rev()
                .find(|(start, _)| *start <= offset)
                .map_or(0, |(_, number)| *number)
        };
        // Reference definitions: `[label]: target` at a line's start.
        for (index, (start, number)) in starts.iter().enumerate() {
            let end = starts.get(index + 1).map_or(clean.len(), |(next, _)| *next);
            let trimmed = clean[*start..end].trim_start();
            if trimmed.starts_with('[')
                && let Some(close) = trimmed.find("]:")
                && let Some(target) = trimmed[close + 2..].split_whitespace().next()
            {
                links.push(Link {
                    line: *number,
                    target: target.trim_matches(|c| c == '<' || c == '>').to_string(),
                });
            }
        }
        // Inline links and images: `[text](target)`.
        let mut search = 0;
        while let Some(found) = clean[search..].find("](") {
            let middle = search + found;
            search = middle + 2;
            if !clean[..middle].contains('[') {
                continue;
            }
            if let Some(target) = destination(&clean[middle + 2..]) {
                links.push(Link {
                    line: line_at(middle),
                    target,
                });
            }
        }
        paragraph.clear();
    };
    for line in &lines {
        if line.text.trim().is_empty() {
            flush(&mut paragraph, &mut links);
        } else {
            paragraph.push(line);
        }
    }
    flush(&mut paragraph, &mut links);
    links
}

/// `text` with `%XX` escapes decoded.
fn percent_decoded(text: &str) -> String {
    let bytes = text.as_bytes();
    let hex = |byte: u8| char::from(byte).to_digit(16);
    let mut decoded = Vec::with_capacity(bytes.len());
    let mut index = 0;
    while index < bytes.len() {
        if bytes[index] == b'%'
            && index + 2 < bytes.len()
            && let (Some(high), Some(low)) = (hex(bytes[index + 1]), hex(bytes[index + 2]))
        {
            decoded.push((high * 16 + low) as u8);
            index += 3;
        } else {
            decoded.push(bytes[index]);
            index += 1;
        }
    }
    String::from_utf8_lossy(&decoded).into_owned()
}

/// Whether a link leaves the repository's files (a web address or mail).
fn is_external(target: &str) -> bool {
    let lower = target.to_ascii_lowercase();
    lower.starts_with("http://") || lower.starts_with("https://") || lower.starts_with("mailto:")
}

/// `path` with `.` and `..` resolved lexically (the file need not exist).
fn normalised(path: &Path) -> PathBuf {
    let mut result = PathBuf::new();
    for component in path.components() {
        match component {
            Component::ParentDir => {
                result.pop();
            }
            Component::CurDir => {}
            other => result.push(other.as_os_str()),
        }
    }
    result
}

/// What is wrong with `link` in `file`, if anything.
fn problem(
    root: &Path,
    file: &Path,
    link: &Link,
    cache: &mut HashMap<PathBuf, HashSet<String>>,
) -> Option<String> {
    let target = link.target.as_str();
    if target.is_empty() {
        return Some("an empty link".to_string());
    }
    if is_external(target) {
        return None;
    }
    let (path_part, anchor) = match target.split_once('#') {
        Some((path, anchor)) => (path, Some(anchor)),
        None => (target, None),
    };
    let resolved = if path_part.is_empty() {
        file.to_path_buf()
    } else if path_part.starts_with('/') {
        return Some(format!(
            "`{target}`: absolute paths do not resolve on GitHub; use a relative one"
        ));
    } else {
        normalised(
            &file
                .parent()
                .expect("a file's directory")
                .join(percent_decoded(path_part)),
        )
    };
    if !resolved.starts_with(root) {
        return Some(format!("`{target}` leaves the repository"));
    }
    if !resolved.exists() {
        return Some(format!("`{target}`: {} does not exist", resolved.display()));
    }
    let anchor = anchor?;
    if resolved
        .extension()
        .is_none_or(|extension| extension != "md")
    {
        return None;
    }
    let anchors = cache.entry(resolved.clone()).or_insert_with(|| {
        anchors(&fs::read_to_string(&resolved).expect("a readable Markdown file"))
    });
    let wanted = percent_decoded(anchor).to_lowercase();
    if anchors.contains(&wanted) {
        None
    } else {
        let mut known: Vec<&String> = anchors.iter().collect();
        known.sort();
        Some(format!(
            "`{target}`: no heading of {} has the anchor `#{wanted}` (it has: {})",
            resolved.display(),
            known
                .iter()
                .map(|anchor| anchor.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ))
    }
}

#[test]
fn every_relative_link_in_the_documentation_resolves() {
    let root = repository_root();
    let files = documentation_files(&root);
    assert!(
        files.len() > 2,
        "expected the README, the changelog and the docs/ pages, found {files:?}"
    );
    let mut cache = HashMap::new();
    let mut problems = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = fs::read_to_string(file)
            .unwrap_or_else(|error| panic!("cannot read {}: {error}", file.display()));
        for link in links(&text) {
            checked += 1;
            if let Some(problem) = problem(&root, file, &link, &mut cache) {
                let shown = file.strip_prefix(&root).unwrap_or(file);
                problems.push(format!("{}:{}: {problem}", shown.display(), link.line));
            }
        }
    }
    assert!(checked > 0, "no links found in {files:?}");
    assert!(
        problems.is_empty(),
        "{} broken link(s) in the documentation:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

#[test]
fn headings_are_slugged_as_github_slugs_them() {
    assert_eq!(
        slug("Error bars, renders to a target error"),
        "error-bars-renders-to-a-target-error"
    );
    assert_eq!(slug(&heading_text("`lqmc render`")), "lqmc-render");
    assert_eq!(
        slug("Heinrich & Keller's particle study"),
        "heinrich--kellers-particle-study"
    );
    assert_eq!(
        slug("Layered: pbrt-v4's `coateddiffuse`"),
        "layered-pbrt-v4s-coateddiffuse"
    );
    assert_eq!(
        slug(&heading_text("See [the page](a.md) now")),
        "see-the-page-now"
    );
    let text = "# Title\n\n```sh\n# not a heading\n```\n\n## Part\n\n## Part\n\nSetext\n------\n";
    let found = anchors(text);
    for expected in ["title", "part", "part-1", "setext"] {
        assert!(found.contains(expected), "{expected} in {found:?}");
    }
    assert!(!found.contains("not-a-heading"), "{found:?}");
}

#[test]
fn links_in_code_are_not_links() {
    let text = "See [a](a.md) and `[b](b.md)`,\nand [c](c.md#x \"title\").\n\n```\n[d](d.md)\n```\n\n[e]: e.md\n";
    let targets: Vec<String> = links(text).into_iter().map(|link| link.target).collect();
    assert_eq!(
        targets,
        ["a.md", "c.md#x", "e.md"].map(String::from).to_vec()
    );
}
