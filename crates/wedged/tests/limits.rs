//! Limits and cancellation end a run cleanly, as `Outcome::Incomplete`, with no claim beyond what
//! was finished.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use wedged::examples::random_spd_problem;
use wedged::{enumerate, enumerate_with_control, Limits, Method, Outcome, Settings, Stop};

fn settings(method: Method, limits: Limits) -> Settings {
    Settings {
        method,
        limits,
        ..Settings::default()
    }
}

#[test]
fn a_zero_time_limit_stops_at_once() {
    let p = random_spd_problem(8, 1.0, 3);
    for method in Method::ALL {
        let limits = Limits {
            time_limit: Some(Duration::ZERO),
            ..Limits::default()
        };
        let e = enumerate(&p, &settings(method, limits)).unwrap();
        assert_eq!(
            e.outcome,
            Outcome::Incomplete(Stop::TimeLimit(Duration::ZERO))
        );
        assert!(e.rays.is_empty() && e.cones.is_empty());
    }
}

#[test]
fn max_rays_stops_double_description_and_reports_no_ray() {
    let p = random_spd_problem(10, 1.0, 2024);
    let complete = enumerate(&p, &Settings::default()).unwrap();
    assert_eq!(complete.outcome, Outcome::Wedged);
    assert!(complete.info.peak_rays > 1000);
    for method in [Method::PrunedDd, Method::FullDd] {
        let limits = Limits {
            max_rays: Some(1000),
            ..Limits::default()
        };
        let e = enumerate(&p, &settings(method, limits)).unwrap();
        assert_eq!(
            e.outcome,
            Outcome::Incomplete(Stop::MaxRays(1000)),
            "{method}"
        );
        assert!(e.rays.is_empty() && e.cones.is_empty());
        assert!(e.info.rays_after_node.len() < 10, "{method}: stopped early");
        // A limit above the peak changes nothing.
        let limits = Limits {
            max_rays: Some(complete.info.peak_rays + 1),
            ..Limits::default()
        };
        let e = enumerate(&p, &settings(Method::PrunedDd, limits)).unwrap();
        assert_eq!(e.rays, complete.rays);
        assert_eq!(e.cones, complete.cones);
    }
}

#[test]
fn faces_reports_the_checked_rays_it_found() {
    let p = random_spd_problem(7, 3.0, 11);
    let complete = enumerate(&p, &settings(Method::Faces, Limits::default())).unwrap();
    assert!(complete.rays.len() >= 2, "{} rays", complete.rays.len());
    let limits = Limits {
        max_rays: Some(1),
        ..Limits::default()
    };
    let e = enumerate(&p, &settings(Method::Faces, limits)).unwrap();
    assert_eq!(e.outcome, Outcome::Incomplete(Stop::MaxRays(1)));
    assert!(!e.rays.is_empty() && e.rays.len() < complete.rays.len());
    // Each is one of the complete run's rays.
    for ray in &e.rays {
        assert!(complete.rays.iter().any(|r| r.status == ray.status));
    }
    assert!(e.cones.is_empty());
}

#[test]
fn cancellation_from_another_thread_stops_a_long_run() {
    // Dense m = 16 takes about a minute; the flag is set after 200 ms.
    let p = random_spd_problem(16, 1.0, 2024);
    let cancel = AtomicBool::new(false);
    let start = Instant::now();
    let e = std::thread::scope(|s| {
        s.spawn(|| {
            std::thread::sleep(Duration::from_millis(200));
            cancel.store(true, Ordering::Relaxed);
        });
        enumerate_with_control(&p, &Settings::default(), &|_| {}, &cancel).unwrap()
    });
    assert_eq!(e.outcome, Outcome::Incomplete(Stop::Interrupted));
    assert!(e.rays.is_empty());
    // Generous: the run checks the flag between pairs, so it ends within moments.
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "{:?}",
        start.elapsed()
    );
}

#[test]
fn max_memory_bounds_the_ray_store() {
    let p = random_spd_problem(10, 1.0, 2024);
    let complete = enumerate(&p, &Settings::default()).unwrap();
    // peak_bytes is peak_rays times the bytes of one ray: 20 values, 1 + 2 words of bits.
    assert_eq!(
        complete.info.peak_bytes,
        complete.info.peak_rays as u64 * 8 * (20 + 1 + 2)
    );
    let limits = Limits {
        max_memory: Some(complete.info.peak_bytes / 4),
        ..Limits::default()
    };
    let e = enumerate(&p, &settings(Method::PrunedDd, limits)).unwrap();
    assert_eq!(
        e.outcome,
        Outcome::Incomplete(Stop::MaxMemory(complete.info.peak_bytes / 4))
    );
    assert!(e.rays.is_empty());
    assert!(e.info.peak_bytes <= complete.info.peak_bytes / 4 + 8 * 23 * 1000);
    let limits = Limits {
        max_memory: Some(complete.info.peak_bytes),
        ..Limits::default()
    };
    let e = enumerate(&p, &settings(Method::PrunedDd, limits)).unwrap();
    assert_eq!(e.rays, complete.rays);
}
