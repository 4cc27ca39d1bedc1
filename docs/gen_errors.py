"""Writes docs/errors.md, the error catalogue, from the error enums and the tests.

    python3 docs/gen_errors.py > docs/errors.md

For each crate's error enum: every variant with its doc (the cause), its #[error] text
(what the user sees) and the test files that name it as `Enum::Variant` (in a test
directory, or after `#[cfg(test)]` in a source file). Then the CLI's exit statuses, the
fault classes and their tests, the property tests, and the tests marked
`#[ignore = "bug: ..."]` (known defects, each with what it should do).
"""

import glob
import os
import re

CRATES = [
    ("msd-ode", "OdeError"),
    ("msd-signal", "SignalError"),
    ("msd-opt", "OptError"),
    ("msd-modal", "ModalError"),
    ("msd-ident", "IdentError"),
    ("msd-mc", "McError"),
]


def esc(s):
    return s.replace("|", "\\|")


def rust_files():
    """Every Rust file that can hold a test: test directories, and sources (whose
    #[cfg(test)] part counts)."""
    patterns = ["crates/*/tests/**/*.rs", "crates/*/src/**/*.rs", "tests/tests/**/*.rs",
                "xtask/tests/**/*.rs", "xtask/src/**/*.rs"]
    files = set()
    for p in patterns:
        files.update(glob.glob(p, recursive=True))
    return sorted(files)


def test_text(path):
    """The part of a file that is test code."""
    text = open(path, encoding="utf-8").read()
    if "/tests/" in path:
        return text
    return text.split("#[cfg(test)]", 1)[1] if "#[cfg(test)]" in text else ""


TESTS = {path: test_text(path) for path in rust_files()}


def tests_for(enum, name):
    pattern = re.compile(r"\b" + enum + r"::" + name + r"\b")
    hits = sorted(p for p, text in TESTS.items() if pattern.search(text))
    return ", ".join("`" + h + "`" for h in hits) or "—"


def variants(path, enum):
    src = open(path, encoding="utf-8").read()
    body = src[src.index("pub enum " + enum):]
    body = body[body.index("{") + 1:body.index("\n}\n")]
    lines = body.split("\n")
    i, doc, msg, res = 0, [], None, []
    while i < len(lines):
        line = lines[i].strip()
        if line.startswith("///"):
            doc.append(line[3:].strip())
            i += 1
            continue
        if line.startswith("#[error("):
            acc = line
            while not acc.endswith(")]"):
                i += 1
                acc += " " + lines[i].strip()
            msg = acc[len("#[error("):-2]
            i += 1
            continue
        m = re.match(r"([A-Z][A-Za-z0-9]+)\b", line)
        if m and msg is not None:
            # The cause is the doc's first paragraph (an example below it stays out).
            cause = doc[: doc.index("")] if "" in doc else doc
            res.append((m.group(1), " ".join(cause), msg))
            doc, msg = [], None
            depth = line.count("{") + line.count("(") - line.count("}") - line.count(")")
            while depth > 0:
                i += 1
                depth += (lines[i].count("{") + lines[i].count("(")
                          - lines[i].count("}") - lines[i].count(")"))
        i += 1
    return res


def ignored_bugs():
    """(file, test, reason) of every test ignored as a known bug."""
    out = []
    pattern = re.compile(r'^[ \t]*#\[ignore = "bug: ([^\n]*?)"\][ \t]*\n\s*fn (\w+)', re.M)
    for path, text in TESTS.items():
        if "/tests/" not in path:
            continue
        for m in pattern.finditer(text):
            out.append((path, m.group(2), " ".join(m.group(1).replace('\\"', '"').split())))
    return sorted(out)


out = [
    "# Error catalogue",
    "",
    "Every error the crates and the CLI can return: the variant, what causes it, what the user sees",
    "(the `Display` text; `{…}` are filled from the variant's fields, so every message names the",
    "place and the value), and the test files that reach it (they name it as `Enum::Variant`).",
    "Generated from each crate's `error.rs` and the tests by `docs/gen_errors.py`",
    "(`python3 docs/gen_errors.py > docs/errors.md`); a `—` in the last column is a variant no test",
    "reaches yet.",
    "",
]
for crate, enum in CRATES:
    out += ["## `" + crate + "`: `" + enum + "`", "",
            "| variant | cause | message | tests |", "|---|---|---|---|"]
    for name, doc, msg in variants("crates/" + crate + "/src/error.rs", enum):
        text = msg.strip().strip('"').strip()
        shown = ("the lower layer's error, unchanged" if msg == "transparent"
                 else "`` " + esc(text) + " ``")
        out.append("| `" + name + "` | " + esc(doc) + " | " + shown + " | "
                   + tests_for(enum, name) + " |")
    out.append("")

out += [
    "## `msd run` and `cargo xtask experiment` (the CLI): exit status",
    "",
    "| class | cause | what the user sees | exit |",
    "|---|---|---|---|",
    "| `Config` | unknown key, wrong type, missing field or section, duplicated key, out-of-range value (negative mass, dt ≤ 0, duration < dt, NaN…) | one line `file:line:column: message` or `file:line: field = value: expected …`; nothing written | 2 |",
    "| `Data` | missing file, missing CSV column, short row, empty or non-numeric cell, NaN or infinity, non-monotonic or non-uniform time, range outside the data | one line `file: line L, column …: value …, expected …`; nothing written | 2 |",
    "| `Download` | `fetch-data` could not get a data set's archive: connection refused or timed out, an HTTP status other than success, a body shorter than its Content-Length, an archive larger than allowed, not a zip (e.g. a web page), a damaged or missing member, a member of the wrong size or SHA-256 | one line `url: message` naming the status, the bytes expected and received, or the member and both checksums; nothing written into `data/SET/` | 2 |",
    "| `Run` | a stage failed (estimation did not converge to a usable point, a simulation failed, a worker panicked, an output could not be written) | `stage failed: message`; the partial output folder is removed | 1 |",
    "",
    "Tests: `tests/tests/end_to_end/bad_input.rs` (every config and data class), `crates/msd-experiment/tests/experiment/download.rs` (every download class, against a server on 127.0.0.1), `xtask/tests/xtask/cli.rs` and `crates/msd-experiment/tests/experiment/cli.rs` (exit codes",
    "and nothing written on the real binary), `tests/tests/properties/` (generated configs and CSV",
    "files, below).",
    "",
    "## Faults while a run writes",
    "",
    "A run computes everything first, then writes into a hidden staging folder beside the target",
    "(`.<name>.partial-<pid>-<n>`) and moves it onto the target only when complete. Each fault class",
    "is tested in `tests/tests/end_to_end/faults.rs` (writes, with the test-only `msd_experiment::output::inject_fault`",
    "hook for a full disk, a panic, a kill and a failed final move) and `crates/msd-opt/tests/suite/faults.rs`",
    "(a panic inside a multistart worker).",
    "",
    "| fault | what happens | exit |",
    "|---|---|---|",
    "| output folder below a file, or on a read-only file system (`/proc`) | `write failed: cannot create the parent of …: Not a directory` (or the OS reason); nothing written | 1 |",
    "| output folder without write permission | `write failed: cannot create a staging folder for …: Permission denied`; nothing written (root is not stopped by permission bits: checked to succeed) | 1 |",
    "| output path is an existing file | `write failed: output … exists and is not a folder`; the file untouched | 1 |",
    "| disk full midway (first CSV, or results.json, the last file) | `write failed: cannot write results.json: No space left on device (os error 28)`; the half-written staging folder removed; a previous result untouched | 1 |",
    "| the final move fails | `write failed: cannot move the results into …`; the previous result, already moved aside, put back | 1 |",
    "| a panic while writing | unwinds; the staging folder is removed on the way; a previous result untouched | — (panic) |",
    "| the process killed midway (`kill -9`, power cut) | the target untouched (or complete); a hidden staging folder is left, and the next run into the same target removes it (and puts back a previous result a kill left moved aside), leaving those of running processes alone | — (killed) |",
    "| a panic in a multistart worker (msd-opt) | caught on the worker: `OptError::WorkerPanicked` naming the start and the panic message (through estimation: `estimation failed: multistart: the local run of start N panicked: …`) | 1 |",
    "| a panic in the caller's Sobol model on a worker (msd-mc) | caught on the worker: `McError::WorkerPanicked` naming the lowest sample row and the panic message, the same for any thread count; the pool stays usable (`crates/msd-mc/tests/mc/errors.rs`) | — (library) |",
    "",
    "## Property tests",
    "",
    "`tests/tests/properties/` throws generated input at every entry point that takes user input:",
    "mutated shipped configs (deleted, duplicated, retyped, out-of-range and unknown fields) and a",
    "few full runs of mutated small configs; damaged CSV files (truncated rows, empty cells, text,",
    "NaN/inf, huge values, wrong delimiters, duplicated rows, no header, a BOM, CRLF line endings,",
    "blank and comment lines, quoted cells, extra columns) through whole runs; signals, multisines",
    "and PRBS with wild parameters; ode45 and exact-simulator options, Nelder–Mead,",
    "Levenberg–Marquardt and multistart options, msd-ident simulation, residual, frequency-check",
    "and estimation options. The property: never a panic, never a NaN or infinity in an output",
    "that claims success, every refusal a specific error naming the place. CI runs a bounded",
    "number of cases; a longer run is one command:",
    "",
    "```sh",
    "PROPTEST_CASES=10000 cargo test -p msd-tests --test properties",
    "```",
    "",
    "(`PROPTEST_CASES` replaces every property's case count; the full-run property, whose cases",
    "are whole experiments, takes a twentieth of it.)",
    "",
    "## Known defects (ignored tests)",
    "",
    "Each is a failing test marked `#[ignore = \"bug: …\"]` that states what should happen; run them",
    "with `cargo test -- --ignored`. Fixing one means removing its `ignore`.",
    "",
    "| test | file | defect |",
    "|---|---|---|",
]
for path, test, reason in ignored_bugs():
    out.append("| `" + test + "` | `" + path + "` | " + esc(reason) + " |")
out.append("")
print("\n".join(out))
