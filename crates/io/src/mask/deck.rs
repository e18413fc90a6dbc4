//! A KLayout DRC deck (`.lydrc`) of the studio's rules: the checks
//! [`udc_core::mask::geometry_drc`] runs, in KLayout's DRC language, so a fab runs exactly what
//! the export ran. Widths and spaces use the projection metric; corner contacts are the
//! Euclidean spaces under one database unit (polygons that touch at a point).

use udc_core::mask::Tone;
use udc_core::mask::drc::Rules;

/// The deck's text for the drawn layer `(layer, datatype)` of a mask of `tone`.
pub fn drc_deck(rules: &Rules, (layer, datatype): (i16, i16), tone: Tone, design: &str) -> String {
    let (width_rule, width_name, width_what, space_rule, space_name, space_what) = match tone {
        Tone::Open => (
            rules.min_feature_um,
            "min_feature",
            "opening",
            rules.min_gap_um,
            "min_gap",
            "chrome gap",
        ),
        Tone::Chrome => (
            rules.min_gap_um,
            "min_gap",
            "chrome gap",
            rules.min_feature_um,
            "min_feature",
            "opening",
        ),
    };
    let name: String = design
        .chars()
        .filter(|c| c.is_ascii_graphic() || *c == ' ')
        .filter(|c| !matches!(c, '"' | '\\' | '<' | '>' | '&' | '#'))
        .take(80)
        .collect();
    let mut dsl = vec![
        format!("# UDC Studio design rules for {name}."),
        format!(
            "# Layer {layer}/{datatype} is {}: its widths are {width_what}s, its spaces \
             {space_what}s.",
            tone.meaning()
        ),
        "# Run: klayout -b -r this.lydrc -rd input=MASK.gds -rd report=MASK.lyrdb".into(),
        "source($input) if $input".into(),
        "$report ? report(\"UDC Studio design rules\", $report) : report(\"UDC Studio design rules\")"
            .into(),
        // Merged first: KLayout's space check of an unmerged layer measures between the
        // pieces of abutting polygons, splitting one edge pair into several.
        format!("drawn = input({layer}, {datatype}).merged"),
    ];
    if width_rule > 0.0 {
        dsl.push(format!(
            "drawn.width({width_rule:?}.um, projection).output(\"{width_name}\", \"{width_what} \
             narrower than {width_rule} um\")"
        ));
    }
    if space_rule > 0.0 {
        dsl.push(format!(
            "drawn.space({space_rule:?}.um, projection).output(\"{space_name}\", \"{space_what} \
             narrower than {space_rule} um\")"
        ));
    }
    if rules.no_corner_contact {
        dsl.push(
            "drawn.space(0.001.um, euclidian).output(\"corner_contact\", \"features that meet \
             at a corner only\")"
                .into(),
        );
    }
    format!(
        "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<klayout-macro>\n \
         <description>UDC Studio design rules</description>\n <version/>\n \
         <category>drc</category>\n <prolog/>\n <epilog/>\n <doc/>\n \
         <autorun>false</autorun>\n <autorun-early>false</autorun-early>\n <shortcut/>\n \
         <show-in-menu>true</show-in-menu>\n <group-name>drc_scripts</group-name>\n \
         <menu-path>tools_menu.drc.end</menu-path>\n <interpreter>dsl</interpreter>\n \
         <dsl-interpreter-name>drc-dsl-xml</dsl-interpreter-name>\n <text>{}\n</text>\n\
         </klayout-macro>\n",
        dsl.join("\n")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tone_swaps_which_rule_measures_widths() {
        let rules = Rules {
            min_feature_um: 20.0,
            min_gap_um: 3.0,
            ..Rules::default()
        };
        let open = drc_deck(&rules, (1, 0), Tone::Open, "d");
        assert!(open.contains("drawn.width(20.0.um, projection).output(\"min_feature\""));
        assert!(open.contains("drawn.space(3.0.um, projection).output(\"min_gap\""));
        let chrome = drc_deck(&rules, (5, 2), Tone::Chrome, "d");
        assert!(chrome.contains("input(5, 2).merged"));
        assert!(chrome.contains("drawn.width(3.0.um, projection).output(\"min_gap\""));
        assert!(chrome.contains("drawn.space(20.0.um, projection).output(\"min_feature\""));
        let lax = Rules {
            no_corner_contact: false,
            min_gap_um: 0.0,
            ..rules
        };
        let deck = drc_deck(&lax, (1, 0), Tone::Open, "a <b> & \"c\"");
        assert!(!deck.contains("euclidian") && !deck.contains("min_gap"));
        assert!(!deck.contains("<b>"));
    }
}
