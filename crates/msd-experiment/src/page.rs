//! `report.html`: the Markdown report as one self-contained page. The figures are
//! inlined as SVG, there are no scripts, external fonts, style sheets or links, and a
//! print style sheet makes a clean PDF for a lab report: no figure or table split
//! across pages, the experiment's name in the page header, page numbers in the footer.

use pulldown_cmark::{Event, Options, Parser, Tag, TagEnd, html};

/// The page's style: readable on a laptop screen, printable to A4.
const STYLE: &str = r#"
:root { color-scheme: light; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif;
  line-height: 1.5; color: #1a1a1a; background: #fff; max-width: 62rem; margin: 0 auto;
  padding: 1.5rem 1.25rem 3rem; }
h1 { font-size: 1.7rem; margin: 0 0 0.8rem; }
h2 { font-size: 1.3rem; margin: 2rem 0 0.6rem; border-bottom: 1px solid #ccc; padding-bottom: 0.2rem; }
h3 { font-size: 1.1rem; margin: 1.4rem 0 0.5rem; }
code { font-family: ui-monospace, "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: 0.92em;
  background: #f3f3f3; padding: 0 0.2em; border-radius: 3px; }
pre { background: #f3f3f3; padding: 0.6rem 0.8rem; overflow-x: auto; }
pre code { background: none; padding: 0; }
.table { overflow-x: auto; margin: 0.8rem 0; }
table { border-collapse: collapse; font-size: 0.92rem; font-variant-numeric: tabular-nums; }
th, td { border: 1px solid #d0d0d0; padding: 0.25rem 0.6rem; text-align: left; vertical-align: top; }
th { background: #f3f3f3; }
figure { margin: 1.2rem 0; }
figure svg { display: block; width: 100%; height: auto; }
figcaption { font-size: 0.9rem; color: #444; margin-top: 0.3rem; }
figure, table, pre, blockquote { break-inside: avoid; page-break-inside: avoid; }
h1, h2, h3 { break-after: avoid; page-break-after: avoid; }
@media print {
  body { max-width: none; padding: 0; font-size: 10pt; }
  h2 { margin-top: 1.2rem; }
  .table { overflow: visible; }
  figure svg { max-height: 22cm; }
}
"#;

/// The HTML page of the Markdown report `markdown`, titled `title`; `svg(name)` gives
/// the SVG text of the figure whose PNG is `name` (a figure without one keeps its
/// image link, which [`self_contained_problems`] then reports).
pub(crate) fn page(markdown: &str, title: &str, svg: impl Fn(&str) -> Option<String>) -> String {
    let mut body = String::new();
    html::push_html(&mut body, inline_figures(markdown, &svg).into_iter());
    let header = css_string(&format!("{title} · msd toolkit"));
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>{}</title>\n<style>{STYLE}\
         @page {{ size: A4; margin: 18mm 14mm 18mm;\n  \
         @top-center {{ content: {header}; font-size: 8pt; color: #555; }}\n  \
         @bottom-right {{ content: \"page \" counter(page) \" of \" counter(pages); font-size: 8pt; color: #555; }} }}\n\
         </style>\n</head>\n<body>\n{body}</body>\n</html>\n",
        escape(title),
    )
}

/// The report's events with every paragraph that holds only a figure replaced by a
/// `<figure>` with the SVG inline; its caption is the paragraph after it when that is one
/// emphasised sentence (the report's caption, then shown once), else the alt text. Tables
/// are wrapped so that a wide one scrolls instead of widening the page.
fn inline_figures<'a>(markdown: &'a str, svg: &impl Fn(&str) -> Option<String>) -> Vec<Event<'a>> {
    let mut out = Vec::new();
    let mut paragraph: Option<Vec<Event<'a>>> = None;
    // A figure waiting for its caption: its drawing and its alt text.
    let mut pending: Option<(String, String)> = None;
    let flush = |out: &mut Vec<Event<'a>>, pending: &mut Option<(String, String)>| {
        if let Some((drawing, alt)) = pending.take() {
            out.push(Event::Html(figure_html(&drawing, &escape(&alt)).into()));
        }
    };
    for event in Parser::new_ext(markdown, Options::ENABLE_TABLES) {
        match event {
            Event::Start(Tag::Paragraph) => paragraph = Some(Vec::new()),
            Event::End(TagEnd::Paragraph) => {
                let events = paragraph.take().unwrap_or_default();
                if let (Some((drawing, _)), Some(caption)) = (&pending, emphasised(&events)) {
                    out.push(Event::Html(figure_html(drawing, &caption).into()));
                    pending = None;
                    continue;
                }
                flush(&mut out, &mut pending);
                match figure(&events, svg) {
                    Some(found) => pending = Some(found),
                    None => {
                        out.push(Event::Start(Tag::Paragraph));
                        out.extend(events);
                        out.push(Event::End(TagEnd::Paragraph));
                    }
                }
            }
            Event::Start(Tag::Table(_)) => {
                flush(&mut out, &mut pending);
                out.push(Event::Html("<div class=\"table\">".into()));
                out.push(event);
            }
            Event::End(TagEnd::Table) => {
                out.push(event);
                out.push(Event::Html("</div>".into()));
            }
            other => match &mut paragraph {
                Some(events) => events.push(other),
                None => {
                    flush(&mut out, &mut pending);
                    out.push(other);
                }
            },
        }
    }
    flush(&mut out, &mut pending);
    out
}

/// The HTML of a paragraph that is one emphasised run (a figure's caption), else `None`.
fn emphasised(events: &[Event<'_>]) -> Option<String> {
    let (Some(Event::Start(Tag::Emphasis)), Some(Event::End(TagEnd::Emphasis))) =
        (events.first(), events.last())
    else {
        return None;
    };
    let inner = &events[1..events.len() - 1];
    if inner
        .iter()
        .any(|e| matches!(e, Event::End(TagEnd::Emphasis)))
    {
        return None; // two emphasised runs with text between: not one caption
    }
    let mut html_text = String::new();
    html::push_html(&mut html_text, inner.iter().cloned());
    Some(html_text)
}

/// A `<figure>` of `drawing` (inline SVG) with the caption's HTML.
fn figure_html(drawing: &str, caption: &str) -> String {
    format!(
        "<figure>\n{}\n<figcaption>{caption}</figcaption>\n</figure>\n",
        drawing.trim_end()
    )
}

/// The inline SVG (labelled by the alt text) and the alt text of a paragraph that is one
/// image with an SVG twin, else `None`.
fn figure(events: &[Event<'_>], svg: &impl Fn(&str) -> Option<String>) -> Option<(String, String)> {
    let (Some(Event::Start(Tag::Image { dest_url, .. })), Some(Event::End(TagEnd::Image))) =
        (events.first(), events.last())
    else {
        return None;
    };
    let caption: String = events[1..events.len() - 1]
        .iter()
        .filter_map(|e| match e {
            Event::Text(t) | Event::Code(t) => Some(t.as_ref()),
            _ => None,
        })
        .collect();
    let drawing = svg(dest_url)?;
    let start = drawing.find("<svg")?;
    let drawing = drawing[start..].replacen(
        "<svg",
        &format!("<svg role=\"img\" aria-label=\"{}\"", escape(&caption)),
        1,
    );
    Some((drawing, caption))
}

/// `text` with HTML's special characters escaped.
fn escape(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    html::push_html(&mut s, std::iter::once(Event::Text(text.into())));
    s
}

/// `text` as a quoted CSS string.
fn css_string(text: &str) -> String {
    let mut s = String::from("\"");
    for c in text.chars() {
        match c {
            '"' | '\\' => {
                s.push('\\');
                s.push(c);
            }
            '\n' | '\r' => s.push(' '),
            c => s.push(c),
        }
    }
    s.push('"');
    s
}

/// What keeps `page` from being one self-contained file: scripts, external style sheets,
/// fonts, images or frames, remote addresses in attributes or styles. Empty when none.
///
/// ```
/// use msd_experiment::page::self_contained_problems;
/// assert!(self_contained_problems("<p>ok</p>").is_empty());
/// let bad = r#"<img src="fig.png"><script src="https://x.invalid/a.js"></script>"#;
/// let problems = self_contained_problems(bad);
/// assert_eq!(problems.len(), 3, "{problems:?}"); // a script, an image file, a remote source
/// ```
pub fn self_contained_problems(page: &str) -> Vec<String> {
    let lower = page.to_ascii_lowercase();
    let checks = [
        ("<script", "a script"),
        ("<link", "a linked resource"),
        ("<img", "an image file"),
        ("<iframe", "a frame"),
        ("@import", "an imported style sheet"),
        ("@font-face", "a font"),
        ("url(", "a resource in a style"),
        ("src=\"http", "a remote source"),
        ("href=\"http", "a remote link"),
        ("href=\"//", "a remote link"),
    ];
    checks
        .iter()
        .filter(|(needle, _)| lower.contains(needle))
        .map(|(needle, what)| format!("{what} (`{needle}`)"))
        .collect()
}

/// Writes `report.md` and `report.html` (titled `title`, each figure's SVG inlined from
/// the staging folder) into `staging`.
pub(crate) fn write_pages(
    staging: &crate::output::Staging,
    markdown: &str,
    title: &str,
) -> crate::error::Result<()> {
    staging.write("report.md", markdown.as_bytes())?;
    let svg = |png: &str| {
        let name = png.strip_suffix(".png")?;
        std::fs::read_to_string(staging.path().join(format!("{name}.svg"))).ok()
    };
    staging.write("report.html", page(markdown, title, svg).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn svg(name: &str) -> Option<String> {
        (name == "fig.png").then(|| "<svg width=\"10\"></svg>".to_string())
    }

    #[test]
    fn a_figure_is_captioned_once_by_the_reports_caption() {
        let html = page(
            "![alt text](fig.png)\n\n*Figure 1 — the fit, `x` in mm.*\n\nNext.\n",
            "t",
            svg,
        );
        assert_eq!(html.matches("<figcaption>").count(), 1, "{html}");
        assert!(
            html.contains("<figcaption>Figure 1 — the fit, <code>x</code> in mm.</figcaption>"),
            "{html}"
        );
        assert!(
            !html.contains("<em>Figure 1"),
            "the caption is shown twice: {html}"
        );
        assert!(html.contains("<p>Next.</p>"));
    }

    #[test]
    fn a_figure_without_a_caption_keeps_its_alt_text_and_the_next_paragraph() {
        let html = page(
            "![alt text](fig.png)\n\nA paragraph, *partly* emphasised.\n",
            "t",
            svg,
        );
        assert!(html.contains("<figcaption>alt text</figcaption>"), "{html}");
        assert!(
            html.contains("<p>A paragraph, <em>partly</em> emphasised.</p>"),
            "{html}"
        );
        let last = page("text\n\n![alt text](fig.png)\n", "t", svg);
        assert!(last.contains("<figcaption>alt text</figcaption>"), "{last}");
    }
}
