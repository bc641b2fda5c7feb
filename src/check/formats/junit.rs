//! JUnit XML, as GitHub, GitLab and Jenkins read it: one `testsuite` named after the suite,
//! one `testcase` a picture (`classname` the line, `name` the picture, `time` the line's
//! seconds), a `failure` for a picture that fails and an `error` for one not made, the
//! explanation and the renderer's last words in `system-out`.

use super::{message, overview, renderer_said, seconds};
use crate::check::{Checked, Group, Status};

/// The XML of `checked`.
pub fn xml(checked: &Checked, groups: &[Group]) -> String {
    let failures = checked
        .graded
        .iter()
        .filter(|g| g.status == Status::Fail)
        .count();
    let errors = checked
        .graded
        .iter()
        .filter(|g| g.status == Status::Error)
        .count();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    xml.push_str(&format!(
        "<testsuites name=\"raycast check\" tests=\"{}\" failures=\"{failures}\" errors=\"{errors}\" time=\"{:.3}\">\n",
        checked.graded.len(),
        seconds(checked)
    ));
    xml.push_str(&format!(
        "  <testsuite name=\"raycast check\" tests=\"{}\" failures=\"{failures}\" errors=\"{errors}\" skipped=\"0\" time=\"{:.3}\">\n",
        checked.graded.len(),
        seconds(checked)
    ));
    for g in &checked.graded {
        xml.push_str(&format!(
            "    <testcase classname=\"{}\" name=\"{}\" time=\"{:.3}\">\n",
            escape(&g.command),
            escape(&g.name),
            g.seconds
        ));
        let element = match g.status {
            Status::Pass => None,
            Status::Fail => Some("failure"),
            Status::Error => Some("error"),
        };
        if let Some(element) = element {
            let kind = g
                .findings
                .first()
                .map(|f| f.code())
                .unwrap_or_else(|| "unknown".into());
            xml.push_str(&format!(
                "      <{element} message=\"{}\" type=\"{}\">{}</{element}>\n",
                escape(&message(g)),
                escape(&kind),
                escape(&g.explanation)
            ));
        }
        // The explanation is the failure's text: here only what ran and what it said.
        let ran = format!(
            "$ {}\n{}",
            g.command,
            renderer_said(&crate::check::untrusted::tail(&g.stderr))
        );
        xml.push_str(&format!(
            "      <system-out>{}</system-out>\n    </testcase>\n",
            escape(&ran)
        ));
    }
    xml.push_str(&format!(
        "    <system-out>{}</system-out>\n",
        escape(&overview(checked, groups))
    ));
    xml.push_str("  </testsuite>\n</testsuites>\n");
    xml
}

/// Text made safe in XML, in an element or an attribute: the report's HTML escape (its five
/// entities are XML's too), after the characters XML 1.0 cannot hold (controls other than tab
/// and line breaks) become U+FFFD.
fn escape(text: &str) -> String {
    let allowed: String = text
        .chars()
        .map(|c| match c {
            '\t' | '\n' | '\r' => c,
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => '\u{FFFD}',
            c => c,
        })
        .collect();
    crate::check::untrusted::html(&allowed)
}

#[cfg(test)]
mod tests {
    #[test]
    fn text_is_escaped_for_xml_and_controls_replaced() {
        assert_eq!(
            super::escape("a<b&\"'\u{1}\tc\n"),
            "a&lt;b&amp;&quot;&#39;\u{FFFD}\tc\n"
        );
    }
}
