use super::*;

/// A pattern run left with an undecided contact set: incomplete, the set listed, the
/// pattern's witness and margin, the pattern info with the method.
#[test]
fn an_undecided_pattern_run_is_incomplete_in_the_json() {
    use wedged::patterns::{Pattern, PatternMethod, PatternSettings, Patterns};
    use wedged::{ContactPattern, NodeStatus, Stop};
    let problem = Problem::new(3, nalgebra::DMatrix::identity(6, 6), 1.0).unwrap();
    let answer = Answer::Patterns(Patterns {
        outcome: Outcome::Incomplete(Stop::Undecided),
        patterns: vec![Pattern {
            pattern: vec![ContactPattern::Contact, ContactPattern::Separated],
            status: vec![NodeStatus::Slip, NodeStatus::Separated],
            u: vec![0.0, 0.5, 0.5, 0.25, 0.0, 0.0],
            r: vec![1.0, 0.5, 0.5, 0.0, 0.0, 0.0],
            margin: 0.25,
        }],
        undecided: vec![Undecided {
            contact: vec![true, true],
            reason: "stalled".to_string(),
        }],
        info: PatternInfo {
            socps: 7,
            ..PatternInfo::default()
        },
        certificate: None,
        shard: None,
    });
    let choice = Choice::Patterns(PatternSettings {
        method: PatternMethod::Pyramid { faces: 12 },
        ..PatternSettings::default()
    });
    let json: serde_json::Value =
        serde_json::from_str(&to_json(&problem, &choice, &answer, None, None)).unwrap();
    assert_eq!(json["complete"], false);
    assert_eq!(json["outcome"], "incomplete");
    assert_eq!(
        json["stopped"],
        "the solver could not decide some contact sets"
    );
    assert_eq!(json["method"], "pyramid");
    assert_eq!(json["rays"], serde_json::json!([]));
    assert_eq!(json["cones"], serde_json::json!([]));
    assert_eq!(
        json["undecided"],
        serde_json::json!([{"contact": [true, true], "reason": "stalled"}])
    );
    assert_eq!(
        json["patterns"],
        serde_json::json!([{
            "pattern": ["contact", "separated"],
            "status": ["slip", "separated"],
            "u": [0.0, 0.5, 0.5, 0.25, 0.0, 0.0],
            "r": [1.0, 0.5, 0.5, 0.0, 0.0, 0.0],
            "margin": 0.25
        }])
    );
    let info = json["info"].as_object().unwrap();
    assert_eq!(info["method"], "pyramid");
    assert_eq!(info["pyramid_faces"], 12);
    assert_eq!(info["socps"], 7);
    // method, pyramid_faces, the 23 fields of PatternInfo and peak_rss_bytes.
    assert_eq!(info.len(), 26, "{info:?}");
}

#[test]
fn layout_is_shallow_pretty_and_valid() {
    let value = serde_json::json!({
        "a": 1,
        "list": [{"x": [1, 2], "y": "s"}, {"x": [], "y": "t"}],
        "empty": [],
        "obj": {"k": [3, 4]}
    });
    let mut buf = Vec::new();
    let mut ser = serde_json::Serializer::with_formatter(&mut buf, ShallowPretty::default());
    value.serialize(&mut ser).unwrap();
    let text = String::from_utf8(buf).unwrap();
    let back: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(back, value);
    assert!(
        text.contains("\n    {\"x\":[1,2],\"y\":\"s\"},\n"),
        "{text}"
    );
    assert!(text.contains("\"empty\": []"), "{text}");
    assert!(text.contains("\n    \"k\": [3,4]\n"), "{text}");
}
