//! What a run reports: the pieces of either kind of enumeration as one list ([`answer`]), the
//! human-readable tables on stdout ([`summary`], and [`critical`] for `critical` and
//! `sweep`), the JSON format ([`json`]) and atomic output files ([`files`]).

pub mod answer;
pub mod critical;
pub mod files;
pub mod json;
pub mod merge;
pub mod summary;

/// A number with at most 4 significant digits, for labels.
pub fn sig4(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".to_string();
    }
    let e = v.abs().log10().floor() as i32;
    let s = if (-3..6).contains(&e) {
        let decimals = (3 - e).max(0) as usize;
        trim_zeros(&format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.3e}");
        match s.split_once('e') {
            Some((m, x)) => format!("{}e{}", trim_zeros(m), x),
            None => s,
        }
    };
    if s == "-0" {
        "0".to_string()
    } else {
        s
    }
}

/// An upper end of `mu*` alone (an incomplete run's checked witness), to ten digits rounded up
/// ([`critical::bound`]): `mu* <= X` must hold as printed.
pub fn upper_text(upper: f64) -> String {
    critical::bound(upper, 10, critical::Round::Up)
}

/// Strips trailing zeros of a decimal number's fraction.
pub fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    /// An upper end alone (merge, study and the coarser meshes' lines) is rounded up, where
    /// nine decimals to the nearest had printed 1.697351394, below the end it stands for.
    #[test]
    fn an_upper_end_is_rounded_up() {
        assert_eq!(super::upper_text(1.697_351_394_444_804_7), "1.697351395");
        assert_eq!(super::upper_text(2.0), "2");
    }
}
