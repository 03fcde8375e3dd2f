//! Every page of the user's manual (and the README) that holds a Rust snippet is compiled as
//! doctests (`src/lib.rs`, module `manual`), and no snippet is left untagged (rustdoc would
//! compile an untagged block as Rust, mdBook would show it as plain text).

use std::path::{Path, PathBuf};

fn pages(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("docs/src is readable") {
        let p = e.expect("a directory entry").path();
        if p.is_dir() {
            pages(&p, out);
        } else if p.extension().is_some_and(|x| x == "md") {
            out.push(p);
        }
    }
}

#[test]
fn every_page_with_rust_is_a_doctest() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib = std::fs::read_to_string(root.join("src/lib.rs")).expect("src/lib.rs");
    let mut all = vec![root.join("README.md")];
    pages(&root.join("docs/src"), &mut all);
    let mut with_rust = 0;
    for p in all {
        let text = std::fs::read_to_string(&p).expect("a page");
        let rel = p.strip_prefix(root).expect("inside the repository");
        let mut open = false;
        for (i, line) in text.lines().enumerate() {
            if let Some(tag) = line.strip_prefix("```") {
                if !open {
                    assert!(
                        !tag.trim().is_empty(),
                        "{}:{}: a code block without a language tag",
                        rel.display(),
                        i + 1
                    );
                }
                open = !open;
            }
        }
        if text.contains("```rust") {
            with_rust += 1;
            let include = format!("include_str!(\"../{}\")", rel.display());
            assert!(
                lib.contains(&include),
                "{} has Rust snippets but src/lib.rs does not compile it ({include})",
                rel.display()
            );
        }
    }
    assert!(with_rust >= 3, "only {with_rust} pages with Rust snippets");
}

#[test]
fn every_relative_link_of_the_manual_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut all = vec![root.join("README.md"), root.join("docs/architecture.md")];
    pages(&root.join("docs/src"), &mut all);
    let mut checked = 0;
    for p in all {
        let text = std::fs::read_to_string(&p).expect("a page");
        let dir = p.parent().expect("a page's folder");
        for (start, _) in text.match_indices("](") {
            let rest = &text[start + 2..];
            let Some(end) = rest.find(')') else { continue };
            let target = rest[..end].split('#').next().unwrap_or_default();
            if target.is_empty() || target.contains("://") || target.contains(' ') {
                continue;
            }
            checked += 1;
            assert!(
                dir.join(target).exists(),
                "{}: the link to {target} does not resolve",
                p.strip_prefix(root).expect("inside").display()
            );
        }
    }
    assert!(checked > 30, "only {checked} links checked");
}
