//! Other units per node: `S K S`, node `i`'s block scaled by `s_i` (here from 1e-3 to 1e3), is
//! the same wedged problem (`u_i / s_i`, `r_i s_i`: signs, complementarity and friction cones are
//! per node). A mesh whose stiffness varies by orders of magnitude looks like this. The 2D rays
//! must keep their statuses and the cones their rays.

use wedged::examples::{node_scaled, random_spd_problem_dim};
use wedged::{enumerate, Method, Settings};

#[test]
fn per_node_units_do_not_change_the_2d_rays() {
    let scales = [1e-3, 1e3, 1.0, 31.6, 0.0316, 1e2];
    let mut compared = 0;
    for seed in 0..20u64 {
        let m = 2 + (seed % 5) as usize;
        let base = random_spd_problem_dim(2, m, 1.5, 500 + seed);
        let scaled = node_scaled(&base, &scales);
        for method in [Method::PrunedDd, Method::Faces] {
            let settings = Settings {
                method,
                ..Settings::default()
            };
            let a = enumerate(&base, &settings).unwrap();
            let b = enumerate(&scaled, &settings).unwrap();
            let statuses = |e: &wedged::Enumeration| -> Vec<Vec<wedged::NodeStatus>> {
                e.rays.iter().map(|r| r.status.clone()).collect()
            };
            assert_eq!(statuses(&a), statuses(&b), "seed {seed}, {method:?}");
            let cones = |e: &wedged::Enumeration| -> Vec<Vec<usize>> {
                e.cones.iter().map(|c| c.rays.clone()).collect()
            };
            assert_eq!(cones(&a), cones(&b), "seed {seed}, {method:?}");
            compared += 1;
        }
    }
    assert_eq!(compared, 40);
}
