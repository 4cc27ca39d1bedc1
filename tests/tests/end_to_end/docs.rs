//! The newcomer's docs stay true (issue 45): every guide the index lists exists and shows a
//! worked example; every config a guide or the README names is shipped; the paper's spec
//! is inside the repository.

use msd_tests::root;

/// The `configs/….toml` paths a text names.
fn configs_named(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("configs/") {
        let tail = &rest[at..];
        let end = tail
            .find(|c: char| !(c.is_ascii_alphanumeric() || "/-_.*".contains(c)))
            .unwrap_or(tail.len());
        let path = tail[..end].trim_end_matches('.');
        if path.ends_with(".toml") && !path.contains('*') {
            found.push(path.to_string());
        }
        rest = &tail[end..];
    }
    found
}

#[test]
fn every_guide_is_listed_shipped_and_worked() {
    let guides = root().join("docs/guides");
    let index = std::fs::read_to_string(guides.join("README.md")).unwrap();
    let mut listed = 0;
    for entry in std::fs::read_dir(&guides).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name == "README.md" {
            continue;
        }
        assert!(
            index.contains(&format!("({name})")),
            "{name} is not listed in docs/guides/README.md"
        );
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains("```text\n$ "),
            "{name}: no worked example with its output"
        );
        listed += 1;
    }
    assert!(listed >= 6, "{listed} guides");
}

#[test]
fn every_config_the_docs_name_is_shipped() {
    let mut docs = vec![root().join("README.md"), root().join("configs/README.md")];
    for entry in std::fs::read_dir(root().join("docs/guides")).unwrap() {
        docs.push(entry.unwrap().path());
    }
    for doc in docs {
        let text = std::fs::read_to_string(&doc).unwrap();
        for config in configs_named(&text) {
            assert!(
                root().join(&config).is_file(),
                "{}: names {config}, which is not shipped",
                doc.display()
            );
        }
    }
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    assert!(
        configs_named(&readme).len() > 10,
        "the README names too few configs to check"
    );
    assert!(root().join("docs/paper-experiment.md").is_file());
}
