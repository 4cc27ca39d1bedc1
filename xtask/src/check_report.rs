//! `cargo xtask check-report`: a run's `report.html` opened in headless Chromium.
//!
//! The page is checked three ways: as text (one self-contained file, a figure for every
//! figure of `report.md`, the same sections), in the browser's layout (a copy with a
//! probe script reports images that failed to load, figures drawn with no size, a page
//! wider than a laptop screen, and figures or tables that a page break may split), and
//! as the browser's own outputs: no console message, a screenshot that is not blank and
//! a PDF with pages.

use msd_experiment::{ExperimentError, Result};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The laptop screen the page must fit, CSS pixels.
const SCREEN: (u32, u32) = (1366, 900);

/// What the browser saw.
#[derive(Debug)]
pub struct Check {
    /// Inline SVG figures laid out with a size.
    pub figures: usize,
    /// Pages of the printed PDF.
    pub pdf_pages: usize,
    /// Share of screenshot pixels that are not the background.
    pub screenshot_ink: f64,
}

fn fail(message: String) -> ExperimentError {
    ExperimentError::run("check-report", message)
}

/// Runs every check on `dir/report.html` (with `dir/report.md` beside it), writing the
/// screenshot and PDF into `dir/browser/`.
pub fn check(dir: &Path) -> Result<Check> {
    let html_path = dir.join("report.html");
    let html = std::fs::read_to_string(&html_path)
        .map_err(|e| fail(format!("cannot read {}: {e}", html_path.display())))?;
    let markdown = std::fs::read_to_string(dir.join("report.md"))
        .map_err(|e| fail(format!("cannot read report.md in {}: {e}", dir.display())))?;
    let figures = check_text(&html, &markdown)?;
    browser(&html_path, figures, &dir.join("browser"))
}

/// The browser's checks of the page at `html_path`, which must draw `figures` figures;
/// the screenshot, PDF and the browser's logs go to `out`.
pub fn browser(html_path: &Path, figures: usize, out: &Path) -> Result<Check> {
    let html = std::fs::read_to_string(html_path)
        .map_err(|e| fail(format!("cannot read {}: {e}", html_path.display())))?;
    std::fs::create_dir_all(out)
        .map_err(|e| fail(format!("cannot create {}: {e}", out.display())))?;
    let chromium = Chromium::find(out)?;
    chromium.probe(&html, figures, out)?;
    let screenshot = out.join("screenshot.png");
    let shot = chromium.run(
        html_path,
        &out.join("screenshot"),
        &[format!("--screenshot={}", screenshot.display())],
    )?;
    let console = Chromium::console(&shot);
    if !console.is_empty() {
        return Err(fail(format!(
            "the page logged to the console:\n{}",
            console.join("\n")
        )));
    }
    let screenshot_ink = ink(&screenshot)?;
    if screenshot_ink < 0.01 {
        return Err(fail(format!(
            "the screenshot {} is blank ({:.2} % of its pixels differ from the background)",
            screenshot.display(),
            100.0 * screenshot_ink
        )));
    }
    let pdf = out.join("report.pdf");
    chromium.run(
        html_path,
        &out.join("pdf"),
        &[
            "--no-pdf-header-footer".into(),
            format!("--print-to-pdf={}", pdf.display()),
        ],
    )?;
    let pdf_pages = pdf_pages(&pdf)?;
    Ok(Check {
        figures,
        pdf_pages,
        screenshot_ink,
    })
}

/// The text checks; returns the number of figures.
fn check_text(html: &str, markdown: &str) -> Result<usize> {
    let problems = msd_experiment::page::self_contained_problems(html);
    if !problems.is_empty() {
        return Err(fail(format!(
            "report.html is not self-contained: it has {}",
            problems.join(", ")
        )));
    }
    // A number that is not one: NaN or an infinity printed where a value should be.
    let not_numbers: Vec<&str> = markdown
        .split(|c: char| !(c.is_alphanumeric() || c == '-'))
        .filter(|w| matches!(*w, "NaN" | "nan" | "inf" | "-inf" | "Inf"))
        .collect();
    if !not_numbers.is_empty() {
        return Err(fail(format!(
            "report.md prints {} where numbers belong (`{}`)",
            not_numbers.len(),
            not_numbers[0]
        )));
    }
    let figures = markdown.lines().filter(|l| l.starts_with("![")).count();
    // Each inline figure on its own: their coordinates are their own.
    let overlaps: Vec<String> = html.split("<svg").skip(1).flat_map(text_overlaps).collect();
    if !overlaps.is_empty() {
        return Err(fail(format!(
            "text overlaps in the figures: {}",
            overlaps.join("; ")
        )));
    }
    let inline = html.matches("<figure>").count();
    if inline != figures {
        return Err(fail(format!(
            "report.md has {figures} figures, report.html {inline} inline"
        )));
    }
    for heading in markdown.lines().filter_map(|l| l.strip_prefix("## ")) {
        if !html.contains(&format!("<h2>{heading}</h2>")) {
            return Err(fail(format!("report.html lacks the section `{heading}`")));
        }
    }
    Ok(figures)
}

/// One horizontal text of an SVG figure: its estimated box (DejaVu Sans averages about
/// 0.55 em a character; the box is the em square's height) and its text.
struct TextBox {
    x: [f64; 2],
    y: [f64; 2],
    text: String,
}

/// The pairs of horizontal texts in one figure's `svg` whose boxes overlap
/// by more than a quarter of the smaller (a rotated text is left out; the same text
/// drawn twice at one place is not an overlap).
fn text_overlaps(svg: &str) -> Vec<String> {
    let mut boxes: Vec<TextBox> = Vec::new();
    let mut found = Vec::new();
    for element in svg.split("<text").skip(1) {
        let Some((attributes, rest)) = element.split_once('>') else {
            continue;
        };
        let text = rest
            .split("</text>")
            .next()
            .unwrap_or("")
            .trim()
            .to_string();
        let Some(b) = text_box(attributes, text) else {
            continue;
        };
        for other in &boxes {
            let same = other.text == b.text && other.x == b.x && other.y == b.y;
            let ix = b.x[1].min(other.x[1]) - b.x[0].max(other.x[0]);
            let iy = b.y[1].min(other.y[1]) - b.y[0].max(other.y[0]);
            let area = |t: &TextBox| (t.x[1] - t.x[0]) * (t.y[1] - t.y[0]);
            if !same && ix > 2.0 && iy > 2.0 && ix * iy > 0.25 * area(&b).min(area(other)) {
                found.push(format!("`{}` and `{}`", other.text, b.text));
            }
        }
        boxes.push(b);
    }
    found
}

/// The box of a `<text …>` element from its attributes, or `None` when rotated or
/// unreadable.
fn text_box(attributes: &str, text: String) -> Option<TextBox> {
    let attribute = |name: &str| {
        let start = attributes.find(&format!(" {name}=\""))? + name.len() + 3;
        let end = attributes[start..].find('"')? + start;
        Some(&attributes[start..end])
    };
    if attribute("transform").is_some() || text.is_empty() {
        return None;
    }
    let (x, y) = (
        attribute("x")?.parse::<f64>().ok()?,
        attribute("y")?.parse::<f64>().ok()?,
    );
    let size = attribute("font-size")
        .and_then(|v| v.parse::<f64>().ok())
        .unwrap_or(12.0);
    let width = 0.55 * size * text.chars().count() as f64;
    let left = match attribute("text-anchor") {
        Some("middle") => x - 0.5 * width,
        Some("end") => x - width,
        _ => x,
    };
    // The baseline's offset: dy in em or ex (ex taken as half an em).
    let shift = attribute("dy").map_or(0.0, |dy| {
        let (number, unit) = dy.split_at(dy.len().saturating_sub(2));
        let value = number.parse::<f64>().unwrap_or(0.0);
        if unit == "ex" {
            0.5 * value * size
        } else {
            value * size
        }
    });
    let baseline = y + shift;
    Some(TextBox {
        x: [left, left + width],
        y: [baseline - 0.8 * size, baseline + 0.2 * size],
        text,
    })
}

/// Headless Chromium, as Debian's `chromium` package installs it (or `$CHROMIUM`).
struct Chromium {
    program: PathBuf,
    /// A fresh, empty user-data folder, removed when done.
    profile: PathBuf,
}

impl Drop for Chromium {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.profile);
    }
}

impl Chromium {
    fn find(scratch: &Path) -> Result<Self> {
        let candidates: Vec<PathBuf> = std::env::var_os("CHROMIUM")
            .map(PathBuf::from)
            .into_iter()
            .chain(
                [
                    "chromium",
                    "chromium-browser",
                    "google-chrome",
                    "google-chrome-stable",
                ]
                .iter()
                .filter_map(|name| on_path(name)),
            )
            .collect();
        let program = candidates
            .into_iter()
            .find(|p| p.is_file())
            .ok_or_else(|| {
                ExperimentError::config(
                    Path::new("CHROMIUM"),
                    "headless Chromium not found: install Debian's `chromium` package \
                 (apt-get install chromium) or set CHROMIUM to the browser's path"
                        .to_string(),
                )
            })?;
        let profile = scratch.join("profile");
        let _ = std::fs::remove_dir_all(&profile);
        std::fs::create_dir_all(&profile)
            .map_err(|e| fail(format!("cannot make a browser profile: {e}")))?;
        Ok(Chromium { program, profile })
    }

    /// Opens `page` with `args` (output logged to `<log>.stdout`, `<log>.stderr`).
    fn run(&self, page: &Path, log: &Path, args: &[String]) -> Result<Output> {
        let page = page
            .canonicalize()
            .map_err(|e| fail(format!("{}: {e}", page.display())))?;
        let mut command = Command::new(&self.program);
        command
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--hide-scrollbars",
                "--enable-logging=stderr",
                "--v=0",
            ])
            .arg(format!("--user-data-dir={}", self.profile.display()))
            .arg(format!("--window-size={},{}", SCREEN.0, SCREEN.1))
            .args(args)
            .arg(format!("file://{}", page.display()));
        let output = wait(command, log, Duration::from_secs(120))?;
        if !output.status.success() {
            return Err(fail(format!(
                "{} failed ({}):\n{}",
                self.program.display(),
                output.status,
                output.stderr
            )));
        }
        Ok(output)
    }

    /// The console messages of `output` (the page has no script: any is an error).
    fn console(output: &Output) -> Vec<String> {
        output
            .stderr
            .lines()
            .filter(|l| l.contains(":CONSOLE"))
            .map(str::to_string)
            .collect()
    }

    /// Loads a copy of the page with a probe script and reads its findings from the DOM.
    fn probe(&self, html: &str, figures: usize, out: &Path) -> Result<()> {
        let copy = out.join("probe.html");
        let page = html.replacen("</body>", &format!("<script>{PROBE}</script></body>"), 1);
        std::fs::write(&copy, page)
            .map_err(|e| fail(format!("cannot write {}: {e}", copy.display())))?;
        let output = self.run(&copy, &out.join("probe"), &["--dump-dom".into()])?;
        let dom = &output.stdout;
        let findings = dom
            .split("<pre id=\"msd-probe\">")
            .nth(1)
            .and_then(|rest| rest.split("</pre>").next())
            .ok_or_else(|| fail("the probe script did not run (no findings in the page)".into()))?;
        let problems: Vec<&str> = findings
            .lines()
            .filter(|l| !l.starts_with("svg "))
            .collect();
        if !problems.is_empty() {
            return Err(fail(format!("in the browser: {}", problems.join("; "))));
        }
        let drawn = findings.lines().filter(|l| l.starts_with("svg ")).count();
        if drawn != figures {
            return Err(fail(format!(
                "{figures} figures, {drawn} drawn with a size"
            )));
        }
        Ok(())
    }
}

/// The probe: one line per finding; `svg …` lines are figures drawn with a size.
const PROBE: &str = r#"
(function () {
  var out = [];
  var images = document.images;
  for (var i = 0; i < images.length; i++) {
    if (!images[i].complete || images[i].naturalWidth === 0) out.push("image failed to load: " + images[i].src);
  }
  document.querySelectorAll("figure svg").forEach(function (s, i) {
    var r = s.getBoundingClientRect();
    if (r.width > 0 && r.height > 0) out.push("svg " + i + " " + Math.round(r.width) + "x" + Math.round(r.height));
    else out.push("figure " + i + " has no size");
  });
  document.querySelectorAll("figure, table").forEach(function (e, i) {
    if (getComputedStyle(e).breakInside !== "avoid") out.push(e.tagName + " " + i + " may be split across pages");
  });
  document.querySelectorAll(".table, pre").forEach(function (e, i) {
    if (e.scrollWidth > e.clientWidth + 1)
      out.push((e.tagName === "PRE" ? "a text block " : "table ") + i + " scrolls sideways (" + e.scrollWidth + " px in " + e.clientWidth + " px): cut in print");
  });
  if (document.documentElement.scrollWidth > window.innerWidth + 1)
    out.push("the page is " + document.documentElement.scrollWidth + " px wide on a " + window.innerWidth + " px screen");
  var pre = document.createElement("pre");
  pre.id = "msd-probe";
  pre.textContent = out.join("\n");
  document.body.appendChild(pre);
})();
"#;

/// What a browser run printed.
struct Output {
    status: std::process::ExitStatus,
    stdout: String,
    stderr: String,
}

/// Runs `command` with its output in files `<log>.stdout` and `<log>.stderr` (a pipe
/// would fill up and stall the browser), killing it after `limit`.
fn wait(mut command: Command, log: &Path, limit: Duration) -> Result<Output> {
    let file = |ext: &str| {
        let path = log.with_extension(ext);
        std::fs::File::create(&path)
            .map(|f| (path.clone(), f))
            .map_err(|e| fail(format!("cannot write {}: {e}", path.display())))
    };
    let (out_path, out) = file("stdout")?;
    let (err_path, err) = file("stderr")?;
    command.stdin(Stdio::null()).stdout(out).stderr(err);
    let mut child = command
        .spawn()
        .map_err(|e| fail(format!("cannot start the browser: {e}")))?;
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if started.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(fail(format!(
                    "the browser did not finish within {} s",
                    limit.as_secs()
                )));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => return Err(fail(format!("waiting for the browser: {e}"))),
        }
    };
    let read = |path: &Path| std::fs::read(path).map(|b| String::from_utf8_lossy(&b).into_owned());
    Ok(Output {
        status,
        stdout: read(&out_path).unwrap_or_default(),
        stderr: read(&err_path).unwrap_or_default(),
    })
}

fn on_path(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join(name))
            .find(|p| p.is_file())
    })
}

/// The share of pixels that differ from the top-left pixel (the background).
fn ink(png: &Path) -> Result<f64> {
    let unreadable = |e: String| fail(format!("cannot read the screenshot {}: {e}", png.display()));
    let file = std::fs::File::open(png).map_err(|e| unreadable(e.to_string()))?;
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    // Palettes and bit depths below 8 expanded: every pixel is whole bytes.
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| unreadable(e.to_string()))?;
    let mut buffer = vec![0; reader.output_buffer_size()];
    let info = reader
        .next_frame(&mut buffer)
        .map_err(|e| unreadable(e.to_string()))?;
    let stride = info.color_type.samples() * usize::from(info.bit_depth as u8).div_ceil(8);
    let pixels: Vec<&[u8]> = buffer[..info.buffer_size()].chunks_exact(stride).collect();
    let Some(&background) = pixels.first() else {
        return Ok(0.0);
    };
    let inked = pixels.iter().filter(|p| **p != background).count();
    Ok(inked as f64 / pixels.len().max(1) as f64)
}

/// The page count of a PDF: the `/Count` of its page tree's root.
fn pdf_pages(pdf: &Path) -> Result<usize> {
    let bytes =
        std::fs::read(pdf).map_err(|e| fail(format!("no PDF at {}: {e}", pdf.display())))?;
    if !bytes.starts_with(b"%PDF-") {
        return Err(fail(format!("{} is not a PDF", pdf.display())));
    }
    let text = String::from_utf8_lossy(&bytes);
    let pages = text
        .split("/Type /Pages")
        .skip(1)
        .filter_map(|tree| {
            let after = tree.split("/Count ").nth(1)?;
            after
                .split(|c: char| !c.is_ascii_digit())
                .next()?
                .parse::<usize>()
                .ok()
        })
        .max()
        .unwrap_or(0);
    if pages == 0 {
        return Err(fail(format!("the PDF {} has no pages", pdf.display())));
    }
    Ok(pages)
}

#[cfg(test)]
mod tests {
    use super::*;

    const FIGURE: &str = r##"<figure><svg viewBox="0 0 100 50" xmlns="http://www.w3.org/2000/svg"><rect width="100" height="50" fill="#336"/></svg></figure>"##;

    fn page(body: &str) -> String {
        format!(
            "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><style>figure, table {{ break-inside: avoid; }}</style></head><body><h1>Run</h1><p>{}</p>{body}</body></html>",
            "text ".repeat(400)
        )
    }

    /// Chromium when the machine has it; CI sets MSD_REQUIRE_BROWSER, so there a
    /// missing browser fails the test instead of skipping it.
    fn with_browser() -> Option<tempfile::TempDir> {
        let dir = tempfile::tempdir().ok()?;
        match Chromium::find(dir.path()) {
            Ok(_) => Some(dir),
            Err(e) if std::env::var_os("MSD_REQUIRE_BROWSER").is_some() => {
                panic!("MSD_REQUIRE_BROWSER is set: {e}")
            }
            Err(e) => {
                eprintln!("browser test skipped: {e}; `cargo xtask check-report` needs it");
                None
            }
        }
    }

    fn browse(body: &str, figures: usize) -> Result<Check> {
        let dir = with_browser().expect("checked by the caller");
        let path = dir.path().join("page.html");
        std::fs::write(&path, page(body)).unwrap();
        let check = browser(&path, figures, &dir.path().join("browser"));
        drop(dir);
        check
    }

    #[test]
    fn text_checks_refuse_what_is_not_self_contained_or_incomplete() {
        let md = "# Run\n\n## Fit\n\n![Fit](fit.png)\n";
        let good = format!("<h2>Fit</h2>{FIGURE}");
        assert_eq!(check_text(&good, md).unwrap(), 1);
        let script = format!("{good}<script>1</script>");
        assert!(
            check_text(&script, md)
                .unwrap_err()
                .to_string()
                .contains("script")
        );
        let no_figure = "<h2>Fit</h2><p>![Fit](fit.png)</p>";
        assert!(
            check_text(no_figure, md)
                .unwrap_err()
                .to_string()
                .contains("1 figures")
        );
        let no_section = FIGURE;
        assert!(
            check_text(no_section, md)
                .unwrap_err()
                .to_string()
                .contains("`Fit`")
        );
    }

    #[test]
    fn overlapping_texts_are_found_and_repeated_or_rotated_ones_are_not() {
        let text = |x: u32, y: u32, t: &str| {
            format!(
                "<text x=\"{x}\" y=\"{y}\" dy=\"0.5ex\" text-anchor=\"end\" font-size=\"16\">\n{t}\n</text>"
            )
        };
        let apart = text(100, 100, "20") + &text(100, 140, "40");
        assert!(text_overlaps(&apart).is_empty());
        let twice = text(100, 100, "1e-1") + &text(100, 100, "1e-1");
        assert!(
            text_overlaps(&twice).is_empty(),
            "the same text drawn twice"
        );
        let clash = text(100, 100, "20") + &text(108, 104, "20");
        assert_eq!(text_overlaps(&clash), ["`20` and `20`"]);
        let rotated = "<text x=\"100\" y=\"100\" transform=\"rotate(270, 100, 100)\" font-size=\"16\">label</text>";
        assert!(text_overlaps(&(text(100, 100, "label") + rotated)).is_empty());
    }

    #[test]
    fn pdf_pages_reads_the_page_tree() {
        let dir = tempfile::tempdir().unwrap();
        let pdf = dir.path().join("a.pdf");
        std::fs::write(
            &pdf,
            "%PDF-1.4\n1 0 obj\n<</Type /Pages\n/Count 3\n/Kids []>>\nendobj\n",
        )
        .unwrap();
        assert_eq!(pdf_pages(&pdf).unwrap(), 3);
        std::fs::write(&pdf, "%PDF-1.4\n<</Type /Pages /Count 0>>").unwrap();
        assert!(
            pdf_pages(&pdf)
                .unwrap_err()
                .to_string()
                .contains("no pages")
        );
        std::fs::write(&pdf, "<html>").unwrap();
        assert!(
            pdf_pages(&pdf)
                .unwrap_err()
                .to_string()
                .contains("not a PDF")
        );
    }

    #[test]
    fn the_browser_passes_a_good_page_and_fails_each_defect() {
        if with_browser().is_none() {
            return;
        }
        let good = browse(FIGURE, 1).expect("a good page");
        assert_eq!(good.figures, 1);
        assert!(
            good.pdf_pages >= 1 && good.screenshot_ink > 0.01,
            "{good:?}"
        );
        let cases = [
            ("<script>console.error('boom')</script>", 0, "console"),
            ("<img src=\"missing.png\">", 0, "image failed to load"),
            (
                "<figure style=\"break-inside: auto\"><svg viewBox=\"0 0 1 1\"></svg></figure>",
                1,
                "split",
            ),
            (
                "<figure><svg width=\"0\" height=\"0\"></svg></figure>",
                1,
                "no size",
            ),
            ("<div style=\"width: 3000px\">wide</div>", 0, "wide"),
            (
                "<div class=\"table\" style=\"overflow-x: auto\"><table><tr><td><div style=\"width: 3000px\">a wide cell</div></td></tr></table></div>",
                0,
                "scrolls sideways",
            ),
            (
                "<pre style=\"overflow-x: auto\"><span style=\"display: inline-block; width: 3000px\">a long line</span></pre>",
                0,
                "text block",
            ),
        ];
        for (body, figures, expected) in cases {
            let err = browse(body, figures).expect_err(body).to_string();
            assert!(err.contains(expected), "{body}: {err}");
        }
    }

    #[test]
    fn a_blank_screenshot_is_refused() {
        if with_browser().is_none() {
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("blank.html");
        std::fs::write(&path, "<!DOCTYPE html><html><body></body></html>").unwrap();
        let err = browser(&path, 0, &dir.path().join("b"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("blank"), "{err}");
    }
}
