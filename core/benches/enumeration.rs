//! Hot pieces and whole parts. `cargo bench -p fixplan-core`.
// criterion_main! generates an undocumented `main`.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use fixplan_core::parts::Accumulator;
use fixplan_core::parts::{
    combinations_in, polygon_clearance, polygon_clearance_below, solve_poses, v2, wrench, AngleSet,
    Feature, Line, LineFeature, LocatorSweep, LocatorWrenches, MaxForceMetric, Metric, PartContact,
    Scratch, Segment, Setup, SweepScratch, SweptSegment,
};
use fixplan_core::{prepare, Case, EnumerateOptions};
use std::hint::black_box;

fn case(name: &str) -> Case {
    let path = format!(
        "{}/../examples/cases/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).expect("bench case");
    let mut c: Case = serde_json::from_str(&text).expect("valid case");
    c.params.top_k = 0;
    c
}

fn pieces(c: &mut Criterion) {
    let lines = [
        Line {
            n: v2(0., -1.),
            c: 0.5,
        },
        Line {
            n: v2(1., 0.),
            c: 3.0,
        },
        Line {
            n: v2(-0.6, 0.8),
            c: 1.0,
        },
    ];
    let locs = [v2(0., 0.), v2(3., 1.), v2(1., 4.)];
    c.bench_function("pose_solution", |b| {
        b.iter(|| solve_poses(black_box(&lines), black_box(&locs)))
    });

    let ws = [
        wrench(v2(0.3, 0.0), v2(0.0, 1.0)),
        wrench(v2(1.0, 0.3), v2(-1.0, 0.0)),
        wrench(v2(0.7, 1.0), v2(0.0, -1.0)),
    ];
    let lw = LocatorWrenches::new(ws).expect("regular");
    c.bench_function("clamp_interval", |b| {
        b.iter(|| lw.clamp_interval(black_box(v2(0., 0.)), v2(0., 1.), v2(1., 0.), -10.0, 10.0))
    });

    let part: Vec<_> = (0..57)
        .map(|i| {
            let t = i as f64 / 57.0 * std::f64::consts::TAU;
            let r = 4.0 + 0.5 * (5.0 * t).sin();
            v2(r * t.cos(), r * t.sin())
        })
        .collect();
    let body = vec![v2(6.0, -0.5), v2(8.0, -0.5), v2(8.0, 0.5), v2(6.0, 0.5)];
    c.bench_function("clearance_body_vs_57_edges", |b| {
        b.iter(|| polygon_clearance(black_box(&body), black_box(&part)))
    });

    let m = MaxForceMetric::new(v2(0.5, 0.5), 0.4);
    let contacts = [
        PartContact {
            q: v2(0.3, 0.0),
            f: v2(0.0, 1.0),
        },
        PartContact {
            q: v2(1.0, 0.7),
            f: v2(-1.0, 0.0),
        },
        PartContact {
            q: v2(0.7, 1.0),
            f: v2(0.0, -1.0),
        },
        PartContact {
            q: v2(0.0, 0.3),
            f: v2(1.0, 0.0),
        },
    ];
    c.bench_function("metric_max_force_256", |b| {
        b.iter(|| m.score(black_box(&contacts)))
    });
    // Top-k mode: a candidate whose score is above the k-th stops at the
    // first applied wrench past it (here half the score, found at once
    // thanks to the hint), and a setup is tested on its locators alone.
    let half = m.score(&contacts).unwrap_or(0.0) / 2.0;
    let mut hint = 0;
    c.bench_function("metric_max_force_256_cut_at_half", |b| {
        b.iter(|| m.score_bounded(black_box(&contacts), half, &mut hint))
    });
    let [l1, l2, l3, _] = contacts;
    c.bench_function("metric_locators_exceed_256_never", |b| {
        b.iter(|| m.locators_exceed(black_box(&[l1, l2, l3]), f64::MAX, &mut 0))
    });
    c.bench_function("clearance_capped_body_vs_57_edges", |b| {
        b.iter(|| polygon_clearance_below(black_box(&body), black_box(&part), 1e-6))
    });
    sweep(c);
}

/// The setup pruning: the angle set of two contacts and the region of the
/// third locator, per `L2`.
fn sweep(c: &mut Criterion) {
    c.bench_function("angle_bands_intersected", |b| {
        b.iter(|| {
            let a = AngleSet::sinusoid_band(black_box(0.3), 2.5, 0.7, 0.0, 4.0, 1e-7);
            let o = AngleSet::sinusoid_band(black_box(-1.0), 2.5, 2.1, -3.0, 1.0, 1e-7);
            a.intersect(&o)
        })
    });
    let line = |o: [f64; 2], dir: f64, len: f64| {
        let u = v2(dir.cos(), dir.sin());
        let n = v2(u.y, -u.x);
        let origin = v2(o[0], o[1]);
        Segment {
            edge: 0,
            s0: 0.0,
            s1: len,
            feature: Feature::Line(LineFeature::new(origin, u, n)),
        }
    };
    let segs = [
        line([0.0, 0.0], 0.0, 6.0),
        line([6.0, 0.0], 1.9, 5.0),
        line([3.0, 5.0], 3.6, 4.0),
    ];
    let swept = segs.each_ref().map(SweptSegment::of);
    let sweep = LocatorSweep::new([&swept[0], &swept[1], &swept[2]], false, 9.0).expect("lines");
    let l2 = v2(4.0, 3.0);
    c.bench_function("pivot_point_angle_bands_per_l2", |b| {
        b.iter(|| sweep.pivot_point(black_box(l2)))
    });
    let pt = sweep
        .pivot_point(l2)
        .expect("some angle keeps both contacts");
    let mut scratch = SweepScratch::default();
    c.bench_function("third_locator_region_per_l2", |b| {
        b.iter(|| {
            let mut n = 0;
            sweep.for_each_third_locator(black_box(&pt), 1, &mut scratch, |_, _| n += 1);
            n
        })
    });
}

fn whole_parts(c: &mut Criterion) {
    let mut g = c.benchmark_group("whole_part_one_thread");
    g.sample_size(20);
    for name in ["rectangle-mm", "gluegun-28", "housing-57"] {
        let k = case(name);
        let p = prepare(&k.part(), &k.kit, &k.params, k.units).expect("valid case");
        let n = p.combination_count();
        g.bench_function(name, |b| {
            b.iter(|| p.enumerate(0..n, EnumerateOptions::this_thread()).result)
        });
        let top10 = p.with_top_k(10, false);
        g.bench_function(format!("{name}_top10_mode"), |b| {
            b.iter(|| {
                top10
                    .enumerate(0..n, EnumerateOptions::this_thread())
                    .result
            })
        });
    }
    g.finish();
}

/// Clamp placement alone on a part with arcs: every setup of
/// `bracket-arcs`, found once, then given its candidates (the arcs' axis
/// lines narrowed by `clamp/arc_reach.rs`), scored and mounted; with full
/// counts and in top-10 mode (where most setups are floored and only
/// counted).
fn clamp_on_arcs(c: &mut Criterion) {
    let k = case("bracket-arcs");
    let p = prepare(&k.part(), &k.kit, &k.params, k.units).expect("valid case");
    let mut setups: Vec<Setup> = Vec::new();
    for (_, combo) in combinations_in(p.segments().len(), 0..u64::MAX) {
        p.setups_of_combination(combo, |s| setups.push(*s));
    }
    let mut g = c.benchmark_group("clamp_placement_bracket_arcs");
    g.sample_size(20);
    for (name, part, acc) in [
        ("full_counts", p.clone(), Accumulator::new(0)),
        (
            "top10_mode",
            p.with_top_k(10, false),
            Accumulator::top_k_mode(10),
        ),
    ] {
        let mut scratch = Scratch::default();
        g.bench_function(name, |b| {
            b.iter(|| {
                let mut acc = acc.clone();
                for s in &setups {
                    part.process_setup(s, &mut acc, &mut scratch);
                }
                acc.counts.candidates
            })
        });
    }
    g.finish();
}

criterion_group!(benches, pieces, whole_parts, clamp_on_arcs);
criterion_main!(benches);
