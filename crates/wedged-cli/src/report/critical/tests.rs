//! Tests of `report/critical.rs`.

use super::*;
use wedged::CriticalInfo;

#[test]
fn bounds_round_outwards_to_the_digits_asked() {
    assert_eq!(bound(1.788_243_05, 8, Round::Up), "1.7882431");
    assert_eq!(bound(1.788_241_37, 8, Round::Down), "1.7882413");
    assert_eq!(bound(1.0, 11, Round::Up), "1");
    assert_eq!(bound(0.5, 11, Round::Down), "0.5");
    assert_eq!(bound(0.999_999_999, 11, Round::Down), "0.999999999");
    assert_eq!(bound(0.999_999_75, 8, Round::Down), "0.99999975");
    assert_eq!(bound(1.5e12, 4, Round::Up), "1.5e12");
    assert_eq!(bound(2.345e-6, 4, Round::Up), "2.345e-6");
    assert_eq!(digits_for(9.4e-7), 8);
    assert_eq!(digits_for(1.0e-9), 10);
    assert_eq!(digits_for(0.0), 15);
    assert_eq!(digits_for(0.5), 4);
}

#[test]
fn the_answer_says_when_the_width_asked_was_not_reached() {
    let result = Critical {
        status: CriticalStatus::Wedged,
        mu_critical: Some(1.788_243_05),
        lower: Some(1.788_241_37),
        upper: Some(1.788_243_05),
        witness: None,
        thresholds: Vec::new(),
        undecided: Vec::new(),
        certificate: None,
        shard: None,
        info: CriticalInfo {
            tol_achieved: (1.788_243_05 - 1.788_241_37) / 1.788_243_05,
            ..CriticalInfo::default()
        },
    };
    assert_eq!(
        answer_line(&result, 1e-9).unwrap(),
        "mu* = 1.7882431 (certified bracket [1.7882413, 1.7882431], relative width 9.4e-7; \
         asked 1e-9: the certificates reach no closer)"
    );
    assert!(!answer_line(&result, 1e-3).unwrap().contains("asked"));
    // A width equal to the one asked, up to the round-off of a difference, is reached.
    let reached = Critical {
        info: CriticalInfo {
            tol_achieved: 1e-9 * (1.0 + 1e-7),
            ..CriticalInfo::default()
        },
        ..result.clone()
    };
    assert!(!answer_line(&reached, 1e-9).unwrap().contains("asked"));
    let never = Critical {
        status: CriticalStatus::Never,
        mu_critical: None,
        lower: None,
        upper: None,
        ..result
    };
    assert!(answer_line(&never, 1e-9)
        .unwrap()
        .starts_with("No friction coefficient wedges this body"));
}
