//! What a run computed, whichever kind of method computed it: the rays and cones of a 2D ray
//! method, or the sign patterns of a pattern method (2D or 3D). The summary, the JSON and the
//! per-piece files read it through [`Answer`].
//!
//! Both kinds describe the solution set as a union of convex pieces. [`Answer::pieces`] gives
//! them in one form, [`Piece`]: a pattern method's maximal patterns as they are (with their
//! witness), a ray method's cones as their pattern, [`Enumeration::cone_status`] and
//! [`Enumeration::cone_centroid`] (the mean of the cone's rays, a solution in its relative
//! interior), in the order of the cones, so that piece `N` is cone `N`.

use wedged::patterns::{PatternMethod, PatternSettings, Patterns};
use wedged::{ContactPattern, Enumeration, NodeStatus, Outcome, Settings};

/// The method asked for, with its settings.
#[derive(Debug, Clone)]
pub enum Choice {
    /// A 2D ray method (`pruned-dd`, `full-dd`, `faces`).
    Rays(Settings),
    /// A sign-pattern method (`bnb`, `pyramid`, `pattern-faces`, `pattern-search`).
    Patterns(PatternSettings),
}

impl Choice {
    /// The method's name, as on the command line and in the JSON.
    pub fn name(&self) -> &'static str {
        match self {
            Choice::Rays(s) => s.method.name(),
            Choice::Patterns(s) => s.method.name(),
        }
    }

    /// The number of faces of the pyramid, for the pyramid method.
    pub fn pyramid_faces(&self) -> Option<usize> {
        match self {
            Choice::Patterns(PatternSettings {
                method: PatternMethod::Pyramid { faces },
                ..
            }) => Some(*faces),
            _ => None,
        }
    }

    /// The fingerprint of a run of this choice on `problem`, as 16 hex digits: the problem's
    /// ([`wedged::Problem::fingerprint`]) with every setting that can change the answer (the
    /// method, the pyramid's faces, the zero tolerance, `--certify`). The parts of one sharded
    /// run carry it, and `wedged merge` refuses parts whose fingerprints differ.
    pub fn fingerprint(&self, problem: &wedged::Problem) -> String {
        let (zero_tol, certify) = match self {
            Choice::Rays(s) => (s.zero_tol, false),
            Choice::Patterns(s) => (s.zero_tol, s.certify),
        };
        let text = format!(
            "enumerate {} {:?} {} {certify}",
            self.name(),
            self.pyramid_faces(),
            zero_tol.to_bits()
        );
        fingerprint(problem, &text)
    }
}

/// The result of a run.
#[derive(Debug, Clone)]
pub enum Answer {
    Rays(Enumeration),
    Patterns(Patterns),
}

/// One convex piece of the solution set, with a solution in its relative interior.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// Per node: contact, separated or grazing throughout the piece.
    pub pattern: Vec<ContactPattern>,
    /// Per node, the status in the piece's relative interior (at the witness).
    pub status: Vec<NodeStatus>,
    /// The witness's displacements and reactions, local frames, `sum r_n = 1`.
    pub u: Vec<f64>,
    pub r: Vec<f64>,
    /// The pattern method's margin (the witness's smallest positive entry); `None` for a cone of
    /// a ray method, whose witness is the mean of its rays.
    pub margin: Option<f64>,
}

impl Answer {
    pub fn outcome(&self) -> Outcome {
        match self {
            Answer::Rays(e) => e.outcome,
            Answer::Patterns(p) => p.outcome,
        }
    }

    /// How a shard's search was split (a run of one shard).
    pub fn shard(&self) -> Option<wedged::ShardReport> {
        match self {
            Answer::Rays(_) => None,
            Answer::Patterns(p) => p.shard,
        }
    }

    /// The reason the run is incomplete, if it is.
    pub fn stopped(&self) -> Option<wedged::Stop> {
        match self.outcome() {
            Outcome::Incomplete(stop) => Some(stop),
            _ => None,
        }
    }

    /// The convex pieces: a pattern run's maximal patterns, a ray run's cones (in cone order).
    pub fn pieces(&self) -> Vec<Piece> {
        self.each_piece().collect()
    }

    /// [`Answer::pieces`] one at a time (each made when asked for: the JSON writes a run's
    /// pieces without holding a copy of them all).
    pub fn each_piece(&self) -> Box<dyn Iterator<Item = Piece> + '_> {
        match self {
            Answer::Rays(e) => Box::new(e.cones.iter().map(|cone| {
                let (u, r) = e.cone_centroid(cone);
                Piece {
                    pattern: cone.pattern.clone(),
                    status: e.cone_status(cone),
                    u,
                    r,
                    margin: None,
                }
            })),
            Answer::Patterns(p) => Box::new(p.patterns.iter().map(|q| Piece {
                pattern: q.pattern.clone(),
                status: q.status.clone(),
                u: q.u.clone(),
                r: q.r.clone(),
                margin: Some(q.margin),
            })),
        }
    }
}

/// The exact certificate of a run: of its rays, or of its sign patterns.
#[derive(Debug, Clone, Copy)]
pub enum Certified<'a> {
    Rays(&'a wedged::certify::Certificate),
    Patterns(&'a wedged::PatternCertificate),
}

impl Certified<'_> {
    pub fn certified(&self) -> bool {
        match self {
            Certified::Rays(c) => c.certified,
            Certified::Patterns(c) => c.certified,
        }
    }

    /// Whether the answer is also proven complete (`None`: not checked).
    pub fn complete(&self) -> Option<bool> {
        match self {
            Certified::Rays(c) => c.complete,
            // The pattern certificate proves completeness or fails.
            Certified::Patterns(c) => Some(c.certified),
        }
    }

    pub fn failures(&self) -> &[String] {
        match self {
            Certified::Rays(c) => &c.failures,
            Certified::Patterns(c) => &c.failures,
        }
    }
}

/// The fingerprint of a run on `problem` with the settings that `settings` spells out, as 16
/// hex digits: the problem's ([`wedged::Problem::fingerprint`]) folded with the text (FNV-1a).
pub fn fingerprint(problem: &wedged::Problem, settings: &str) -> String {
    let mut h = problem.fingerprint();
    for byte in settings.bytes() {
        h ^= u64::from(byte);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use wedged::{enumerate, Problem};

    #[test]
    fn ray_pieces_follow_the_cones() {
        let k = nalgebra::DMatrix::from_row_slice(
            4,
            4,
            &[
                2.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 1.0, 1.0,
            ],
        );
        let problem = Problem::new(2, k, 1.1).unwrap();
        let e = enumerate(&problem, &Settings::default()).unwrap();
        let answer = Answer::Rays(e.clone());
        let pieces = answer.pieces();
        assert_eq!(pieces.len(), e.cones.len());
        for (piece, cone) in pieces.iter().zip(&e.cones) {
            assert_eq!(piece.pattern, cone.pattern);
            assert_eq!(piece.margin, None);
            let r_n: f64 = (0..2).map(|i| piece.r[2 * i]).sum();
            assert!((r_n - 1.0).abs() < 1e-12);
        }
        assert_eq!(Choice::Rays(Settings::default()).name(), "pruned-dd");
        let pyramid = Choice::Patterns(PatternSettings {
            method: PatternMethod::Pyramid { faces: 12 },
            ..PatternSettings::default()
        });
        assert_eq!(
            (pyramid.name(), pyramid.pyramid_faces()),
            ("pyramid", Some(12))
        );
    }
}
