//! Internal checks of the elimination: the degree claim and that `F`
//! vanishes at a known pose.

use super::*;
use std::f64::consts::TAU;

fn rnd(state: &mut u64) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

fn random_contacts(state: &mut u64, circles: usize) -> ([Contact; 3], [V2; 3]) {
    let mut r = |lo: f64, hi: f64| lo + (hi - lo) * rnd(state);
    let contacts = std::array::from_fn(|k| {
        if k < 3 - circles {
            let a: f64 = r(0.0, TAU);
            Contact::Line(Line {
                n: v2(a.cos(), a.sin()),
                c: r(-3.0, 3.0),
            })
        } else {
            Contact::Circle(Circle {
                centre: v2(r(-3.0, 3.0), r(-3.0, 3.0)),
                radius: r(0.2, 5.0),
            })
        }
    });
    let locs = std::array::from_fn(|_| v2(r(-4.0, 4.0), r(-4.0, 4.0)));
    (contacts, locs)
}

fn samples_of_f(red: &Reduced) -> [f64; SAMPLES] {
    let r02 = red.rho0 * red.rho0;
    std::array::from_fn(|m| {
        let [(b1, r1, _), (b2, r2, _)] = red.rows_at(COS16[m], SIN16[m]);
        let det = cross(b1, b2);
        (perp(b2) * r1 - perp(b1) * r2).norm_squared() - r02 * det * det
    })
}

/// The degree claims behind the completeness argument: `F` has degree <= 4
/// (no aliasing from harmonics 5..8 of 16 samples), in fact <= 3, and
/// <= 2 with two lines.
#[test]
fn eliminant_degree() {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    for case in 0..3000 {
        let circles = 1 + case % 3;
        let (contacts, locs) = random_contacts(&mut state, circles);
        let red = Reduced::new(&contacts, &locs).expect("has a circle");
        let v = samples_of_f(&red);
        let sm = red.sample();
        let rel = |x: f64| x / sm.scale_f;
        assert!(rel(Trig::alias(&v)) < 1e-13, "{case}");
        assert!(rel(sm.f.a[4].abs().max(sm.f.b[4].abs())) < 1e-13, "{case}");
        if circles == 1 {
            assert!(rel(sm.f.a[3].abs().max(sm.f.b[3].abs())) < 1e-13, "{case}");
        }
        // D has degree <= 1 and N degree <= 2.
        for t in [&sm.d] {
            for j in 2..=4 {
                assert!(
                    t.a[j].abs().max(t.b[j].abs()) < 1e-13 * sm.max_dhat,
                    "{case}"
                );
            }
        }
        for t in [&sm.nx, &sm.ny].map(Trig::from_samples) {
            for j in 3..=4 {
                assert!(
                    t.a[j].abs().max(t.b[j].abs()) < 1e-13 * sm.max_nhat,
                    "{case}"
                );
            }
        }
    }
}

/// At a pose built to satisfy the equations, `F` vanishes (relative to its
/// terms) and Cramer's `w'` maps back to the pose's `w`.
#[test]
fn eliminant_vanishes_at_a_known_pose() {
    let mut state = 0x1234_5678_9abc_def1u64;
    let mut worst = 0.0f64;
    for case in 0..20000 {
        let circles = 1 + case % 3;
        let (mut contacts, _) = random_contacts(&mut state, circles);
        let theta = TAU * rnd(&mut state);
        let w = v2(4.0 * rnd(&mut state) - 2.0, 4.0 * rnd(&mut state) - 2.0);
        let (s, c) = theta.sin_cos();
        let mut locs = [V2::zeros(); 3];
        for k in 0..3 {
            // Move each feature so that a random point on it is the contact.
            let p = v2(6.0 * rnd(&mut state) - 3.0, 6.0 * rnd(&mut state) - 3.0);
            match &mut contacts[k] {
                Contact::Line(l) => l.c = l.n.dot(&p),
                Contact::Circle(ci) => {
                    let a = TAU * rnd(&mut state);
                    ci.centre = p - v2(a.cos(), a.sin()) * ci.radius;
                }
            }
            locs[k] = rot(c, s, p + w);
        }
        let red = Reduced::new(&contacts, &locs).expect("has a circle");
        let sm = red.sample();
        let (f, _, _) = sm.f.eval3(theta);
        worst = worst.max(f.abs() / sm.scale_f);
        assert!(
            f.abs() < 1e-11 * sm.scale_f,
            "{case}: {f} vs {}",
            sm.scale_f
        );
        let mut starts = [V2::zeros(); 3];
        let k = red.w_starts(c, s, &mut starts);
        let back = |w1: V2| w1 - red.part_shift + rot_t(c, s, red.plate_shift);
        assert!(
            starts[..k].iter().any(|&w1| (back(w1) - w).norm() < 1e-6),
            "{case}: {:?} vs {w}",
            &starts[..k]
        );
    }
    // The coefficient error the root finder is told to expect
    // (ROUNDING_REL) must cover this with a wide margin.
    println!("largest |F| at a solution, relative to its terms: {worst:e}");
    assert!(worst < ROUNDING_REL / 10.0, "{worst:e}");
}

/// Continua built exactly (up to rounding of their inputs) have an `F`
/// within rounding of zero, far below `CONTINUUM_REL`; random setups are
/// far above it.
#[test]
fn continuum_threshold_separates() {
    let mut state = 0xabcd_ef01_2345_6789u64;
    let (mut worst_continuum, mut least_genuine) = (0.0f64, f64::INFINITY);
    for case in 0..5000 {
        let mut r = |lo: f64, hi: f64| lo + (hi - lo) * rnd(&mut state);
        // Concentric circles the part turns in, about plate point x.
        let x = v2(r(-4.0, 4.0), r(-4.0, 4.0));
        let centre = v2(r(-4.0, 4.0), r(-4.0, 4.0));
        let locs = [0, 1, 2].map(|_| v2(r(-4.0, 4.0), r(-4.0, 4.0)));
        let mut contacts = locs.map(|l| {
            Contact::Circle(Circle {
                centre,
                radius: (l - x).norm(),
            })
        });
        if case % 2 == 1 {
            // A line through the centre, its locator at x.
            let a = r(0.0, TAU);
            let n = v2(a.cos(), a.sin());
            contacts[0] = Contact::Line(Line {
                n,
                c: n.dot(&centre),
            });
        }
        let mut l2 = locs;
        if case % 2 == 1 {
            l2[0] = x;
        }
        let red = Reduced::new(&contacts, &l2).expect("has a circle");
        let sm = red.sample();
        worst_continuum = worst_continuum.max(sm.f.max_abs() / sm.scale_f);
        let (rc, rl) = random_contacts(&mut state, 1 + case % 3);
        let red = Reduced::new(&rc, &rl).expect("has a circle");
        let sm = red.sample();
        least_genuine = least_genuine.min(sm.f.max_abs() / sm.scale_f);
    }
    println!("max |F coef| / scale: continua {worst_continuum:e}, random setups at least {least_genuine:e}");
    assert!(worst_continuum < CONTINUUM_REL / 100.0);
    assert!(least_genuine > CONTINUUM_REL * 100.0);
}

/// Why tangential poses are singular setups (docs/model.md, section 13): row `k`
/// of the pose Jacobian is contact `k`'s wrench `(f, L_k x f)` with its
/// force part turned into the part frame, so with rows scaled to unit
/// length `|det J| = |det W| / prod |w_k|` at every pose.
#[test]
fn tangency_measure_is_the_scaled_wrench_determinant() {
    let mut state = 0x0bad_5eed_1234_5678u64;
    for case in 0..5000 {
        let circles = case % 4;
        let (mut contacts, _) = random_contacts(&mut state, circles);
        let theta = TAU * rnd(&mut state);
        let w = v2(4.0 * rnd(&mut state) - 2.0, 4.0 * rnd(&mut state) - 2.0);
        let (s, c) = theta.sin_cos();
        let mut locs = [V2::zeros(); 3];
        let mut wrenches = [Vector3::zeros(); 3];
        for k in 0..3 {
            let p = v2(6.0 * rnd(&mut state) - 3.0, 6.0 * rnd(&mut state) - 3.0);
            // The feature's unit normal at the contact, part frame.
            let u = match &mut contacts[k] {
                Contact::Line(l) => {
                    l.c = l.n.dot(&p);
                    l.n
                }
                Contact::Circle(ci) => {
                    let a = TAU * rnd(&mut state);
                    ci.centre = p - v2(a.cos(), a.sin()) * ci.radius;
                    v2(a.cos(), a.sin())
                }
            };
            locs[k] = rot(c, s, p + w);
            // Contact k's wrench `(f, L_k x f)`, `f` the inward normal.
            let f = -rot(c, s, u);
            wrenches[k] = Vector3::new(f.x, f.y, cross(locs[k], f));
        }
        let det_w = Matrix3::from_columns(&wrenches).determinant();
        let scale: f64 = wrenches.iter().map(|x| x.norm()).product();
        let det_j = scaled_jacobian_det(&contacts, &locs, c, s, w);
        assert!(
            (det_j.abs() - det_w.abs() / scale).abs() <= 1e-12,
            "{case}: det J {det_j} vs det W / prod |w| {}",
            det_w / scale
        );
    }
}
