//! The layering of ARCHITECTURE.md, checked on the code: every `crate::` path of every file
//! under `src/` (outside comments and `#[cfg(test)]` modules) names a stage listed above the
//! file's own stage. The list is read from ARCHITECTURE.md itself, so the document and the code
//! cannot drift apart; a stage of `src/` missing from the list fails too.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The stages of ARCHITECTURE.md in order, from its lines ``N. `name`: ...``.
fn stages() -> Vec<String> {
    let doc = std::fs::read_to_string(root().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let mut out = Vec::new();
    for line in doc.lines() {
        let Some((number, rest)) = line.split_once(". `") else {
            continue;
        };
        if number.is_empty() || !number.chars().all(|c| c.is_ascii_digit()) {
            continue;
        }
        let name = rest.split('`').next().unwrap_or_default();
        assert_eq!(
            number.parse::<usize>().unwrap(),
            out.len() + 1,
            "ARCHITECTURE.md: stage `{name}` is numbered {number}, expected {}",
            out.len() + 1
        );
        out.push(name.to_string());
    }
    out
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.rs` file under `src/` except the command line (`src/bin/`, above every stage) and the
/// crate root.
fn source_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().collect();
        entries.sort_by_key(|e| e.path());
        for e in entries {
            let p = e.path();
            if p.is_dir() {
                if p.file_name().is_some_and(|n| n != "bin") {
                    walk(&p, out);
                }
            } else if p.extension().is_some_and(|x| x == "rs") && p.file_name().unwrap() != "lib.rs"
            {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(&root().join("src"), &mut out);
    out
}

/// The stage of a file: its first path component under `src/`, without `.rs`.
fn stage_of(path: &Path) -> String {
    let rel = path.strip_prefix(root().join("src")).unwrap();
    let first = rel
        .components()
        .next()
        .unwrap()
        .as_os_str()
        .to_string_lossy();
    first.trim_end_matches(".rs").to_string()
}

/// The code of a file without line comments (doc comments included) and without everything
/// from its first `#[cfg(test)]` on (unit tests sit at the end of a file, by house style).
fn code_of(text: &str) -> String {
    let end = text.find("\n#[cfg(test)]").unwrap_or(text.len());
    text[..end]
        .lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The stages a piece of code names: `crate::NAME` anywhere, and the first component of each
/// item of a `use crate::{...}` group.
fn imported_stages(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    let mut i = 0;
    while let Some(k) = code[i..].find("crate::") {
        let start = i + k;
        let before_ok = start == 0
            || !(bytes[start - 1].is_ascii_alphanumeric()
                || bytes[start - 1] == b'_'
                || bytes[start - 1] == b'$');
        let mut j = start + "crate::".len();
        if before_ok {
            if code[j..].starts_with('{') {
                // A group: its items up to the matching brace.
                let mut depth = 0;
                let mut item = String::new();
                let mut items = Vec::new();
                for c in code[j..].chars() {
                    j += c.len_utf8();
                    match c {
                        '{' => {
                            depth += 1;
                            if depth > 1 {
                                item.push(c);
                            }
                        }
                        '}' => {
                            depth -= 1;
                            if depth == 0 {
                                items.push(std::mem::take(&mut item));
                                break;
                            }
                            item.push(c);
                        }
                        ',' if depth == 1 => items.push(std::mem::take(&mut item)),
                        _ => item.push(c),
                    }
                }
                for it in items {
                    let name: String = it
                        .trim()
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                        .collect();
                    if !name.is_empty() {
                        out.push(name);
                    }
                }
            } else {
                let name: String = code[j..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                out.push(name);
            }
        }
        i = j.max(start + 1);
    }
    out
}

/// Items of the crate root that every stage may name: the `assert_near!` macro (exported at
/// the root by `#[macro_export]`) and the version constant.
const ROOT_ITEMS: [&str; 2] = ["assert_near", "VERSION"];

#[test]
fn no_stage_imports_a_higher_one() {
    let order = stages();
    assert!(
        order.len() >= 10,
        "ARCHITECTURE.md lists {} stages",
        order.len()
    );
    let rank: BTreeMap<&str, usize> = order
        .iter()
        .enumerate()
        .map(|(i, s)| (s.as_str(), i))
        .collect();
    let mut violations = Vec::new();
    for file in source_files() {
        let stage = stage_of(&file);
        let Some(&own) = rank.get(stage.as_str()) else {
            violations.push(format!(
                "{}: stage `{stage}` is not listed in ARCHITECTURE.md",
                file.display()
            ));
            continue;
        };
        let code = code_of(&std::fs::read_to_string(&file).unwrap());
        for target in imported_stages(&code) {
            if target == stage || ROOT_ITEMS.contains(&target.as_str()) {
                continue;
            }
            match rank.get(target.as_str()) {
                Some(&r) if r < own => {}
                Some(_) => violations.push(format!(
                    "{}: `{stage}` (stage {}) imports `{target}` (stage {})",
                    file.strip_prefix(root()).unwrap().display(),
                    own + 1,
                    rank[target.as_str()] + 1
                )),
                None => violations.push(format!(
                    "{}: `{stage}` names `crate::{target}`, which is no stage of ARCHITECTURE.md",
                    file.strip_prefix(root()).unwrap().display()
                )),
            }
        }
    }
    assert!(
        violations.is_empty(),
        "layering violations:\n{}",
        violations.join("\n")
    );
}

/// The checker itself: a group, a nested group, a path in an expression, a comment and a test
/// module (tolerance: exact lists).
#[test]
fn the_checker_reads_groups_paths_and_skips_comments_and_tests() {
    let code = code_of(
        "use crate::a::b;\nuse crate::{c::d, e::{f, g}};\n// crate::h\nlet x = crate::i::j(1);\n\
         /// [`crate::k`]\n#[cfg(test)]\nmod tests { use crate::l; }\n",
    );
    assert_eq!(imported_stages(&code), ["a", "c", "e", "i"]);
}

/// Lines per stage (printed; `cargo test --test it architecture -- --nocapture`).
#[test]
fn lines_per_stage() {
    let mut lines: BTreeMap<String, usize> = BTreeMap::new();
    for file in source_files() {
        let n = std::fs::read_to_string(&file).unwrap().lines().count();
        *lines.entry(stage_of(&file)).or_default() += n;
    }
    for s in stages() {
        println!("{:>14} {:>6}", s, lines.get(&s).copied().unwrap_or(0));
    }
    assert!(lines.keys().all(|s| stages().contains(s)));
}
