//! Internal checks of the elimination: the degree claim and that `F`
//! vanishes at a known pose.

use super::*;

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
        for t in [&sm.nx, &sm.ny] {
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
    for case in 0..2000 {
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
}
