import re, subprocess, os
crates = [("msd-ode","OdeError"),("msd-signal","SignalError"),("msd-opt","OptError"),
          ("msd-ident","IdentError"),("msd-mc","McError")]
def esc(s): return s.replace("|", "\\|")
def tests_for(crate, name):
    hits=set()
    for p in [f"crates/{crate}/tests", f"crates/{crate}/src", "tests/tests", "xtask/tests"]:
        if not os.path.isdir(p): continue
        for f in subprocess.run(["grep","-rlE",r"\b"+name+r"\b",p],capture_output=True,text=True).stdout.split():
            txt=open(f).read()
            if "/tests" in f or ("#[cfg(test)]" in txt and name in txt.split("#[cfg(test)]",1)[1]):
                hits.add(f)
    return ", ".join("`"+h+"`" for h in sorted(hits)) or "—"
def variants(path, enum):
    src=open(path).read()
    body=src[src.index("pub enum "+enum):]
    body=body[body.index("{")+1:body.index("\n}\n")]
    lines=body.split("\n"); i=0; doc=[]; msg=None; res=[]
    while i < len(lines):
        l=lines[i].strip()
        if l.startswith("///"):
            doc.append(l[3:].strip()); i+=1; continue
        if l.startswith("#[error("):
            acc=l
            while not acc.endswith(")]"):
                i+=1; acc+=" "+lines[i].strip()
            msg=acc[len("#[error("):-2]; i+=1; continue
        m=re.match(r"([A-Z][A-Za-z0-9]+)\b", l)
        if m and msg is not None:
            res.append((m.group(1)," ".join(doc),msg)); doc=[]; msg=None
            depth=l.count("{")+l.count("(")-l.count("}")-l.count(")")
            while depth>0:
                i+=1; depth+=lines[i].count("{")+lines[i].count("(")-lines[i].count("}")-lines[i].count(")")
        i+=1
    return res
out=["# Error catalogue","",
"Every error the crates and the CLI can return: the variant, what causes it, what the user sees",
"(the `Display` text; `{…}` are filled from the variant's fields, so every message names the",
"place and the value), and the test files that exercise it. Generated from each crate's",
"`error.rs` by the script in `docs/gen_errors.py` (`python3 docs/gen_errors.py > docs/errors.md`);",
"a `—` in the last column is a gap still to close (issue 10).",""]
for crate, enum in crates:
    out += ["## `"+crate+"`: `"+enum+"`","","| variant | cause | message | tests |","|---|---|---|---|"]
    for name, doc, msg in variants("crates/"+crate+"/src/error.rs", enum):
        text = msg.strip().strip('"').strip()
        shown = "the lower layer's error, unchanged" if msg=="transparent" else "`` "+esc(text)+" ``"
        out.append("| `"+name+"` | "+esc(doc)+" | "+shown+" | "+tests_for(crate,name)+" |")
    out.append("")
out += ["## `xtask` (the CLI): exit status",
"",
"| class | cause | what the user sees | exit |",
"|---|---|---|---|",
"| `Config` | unknown key, wrong type, missing field, out-of-range value (negative mass, dt ≤ 0, duration < dt, NaN…) | one line `file: line L, column C: field …: value …, expected …`; nothing written | 2 |",
"| `Data` | missing file, missing CSV column, non-numeric cell, non-monotonic time, range outside the data | one line `file: line L: column …: value …, expected …`; nothing written | 2 |",
"| `Run` | a stage failed (estimation did not converge to a usable point, a simulation failed, an output could not be written, a worker panicked) | `stage failed: message`; the partial output folder is removed | 1 |",
"",
"Tests: `tests/tests/bad_input.rs` (every config and data class), `xtask/tests/cli.rs` (exit codes",
"and nothing written on the real binary).",""]
print("\n".join(out))
