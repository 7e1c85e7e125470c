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

/// Whether `poses` has one within 1e-6 of `pose` in `theta` and `w` (the
/// distance at which SPEC 8.4 merges tangential solutions; simple ones
/// agree to rounding). A tangential pose may instead have a tangential one
/// within 1e-3: where two tangencies coincide (a slot's end circle touching
/// both walls, a locator at the joint), every residual stays below `eps`
/// over a flat neighbourhood, and Newton's method stops anywhere in it
/// (6e-4 off seen), while the closed form gives the exact double root.
fn has_near(poses: &ContactPoses, pose: &ContactPose) -> bool {
    let near = |p: &ContactPose, by: f64| {
        circ_dist(p.pose.theta, pose.pose.theta) <= by && (p.w - pose.w).norm() <= by
    };
    poses
        .iter()
        .any(|p| near(p, BORDERLINE) || (p.tangential && pose.tangential && near(p, 1e-3)))
}

/// Two lines and a circle, the circle at position `at`.
fn with_circle_at(at: usize, lines: [Line; 2], circle: Circle) -> [Contact; 3] {
    let mut k = 0;
    std::array::from_fn(|i| {
        if i == at {
            Contact::Circle(circle)
        } else {
            k += 1;
            Contact::Line(lines[k - 1])
        }
    })
}

/// A slot of half-width `h` along a random lattice direction (quarter
/// turns, so that the lattice setups below are exact): its walls `n . p =
/// h` for `n = +-u_perp`, its end circle of radius `h` at the origin, and
/// integer locators, some of them on the walls' continuation, where the
/// third locator's line of motion touches the end circle (SPEC 8.4's
/// tangential poses at the smooth joint).
fn slot_case(state: &mut u64) -> ([Contact; 3], [V2; 3]) {
    let h = [0.5, 1.0, 1.5, 2.0][(rnd(state) * 4.0) as usize];
    let turn = (rnd(state) * 4.0) as u8;
    let n = crate::geometry::rot90(turn, v2(0.0, 1.0));
    let lines = [Line { n, c: h }, Line { n: -n, c: h }];
    let circle = Circle {
        centre: V2::zeros(),
        radius: h,
    };
    let mut int = |lo: f64, hi: f64| (lo + (hi - lo + 1.0) * rnd(state)).floor();
    let locs = std::array::from_fn(|_| v2(int(-4.0, 4.0), int(-4.0, 4.0)));
    let at = (rnd(state) * 3.0) as usize;
    (with_circle_at(at, lines, circle), locs)
}

/// Issue 32's property: the closed forms for two lines and a circle keep
/// every pose the general elimination keeps and add none, on random
/// setups (crossing lines), on random parallel lines, and on lattice
/// slots full of exact tangencies, where both find the tangential pose
/// (the closed form exactly, the elimination within about 1e-8).
#[test]
fn two_lines_keep_what_the_elimination_keeps() {
    let mut state = 0x2b99_2ddf_a232_49d6u64;
    let (mut compared, mut tangential) = (0, 0);
    for case in 0..30000 {
        let (contacts, locs) = match case % 3 {
            0 => {
                let (c, l) = random_contacts(&mut state, 1);
                let at = (rnd(&mut state) * 3.0) as usize;
                let lines = [0, 1].map(|k| match c[k] {
                    Contact::Line(line) => line,
                    Contact::Circle(_) => unreachable!("two lines first"),
                });
                let Contact::Circle(circle) = c[2] else {
                    unreachable!("the circle last")
                };
                (with_circle_at(at, lines, circle), l)
            }
            1 => {
                let (mut c, l) = random_contacts(&mut state, 1);
                if let (Contact::Line(a), Contact::Line(b)) = (c[0], &mut c[1]) {
                    b.n = if rnd(&mut state) < 0.5 { a.n } else { -a.n };
                }
                (c, l)
            }
            _ => slot_case(&mut state),
        };
        let two = two_lines_of(&contacts, &locs).expect("two lines and a circle");
        let mut found = Found::new();
        if !two_line_poses(&two, &contacts, &locs, (&|_, _| true, None), &mut found) {
            continue; // nearly parallel: the elimination's
        }
        let mine = found.finish();
        let general = eliminated_poses(&contacts, &locs, &|_, _| true);
        for pose in general.iter() {
            assert!(
                has_near(&mine, pose),
                "{case}: {contacts:?} {locs:?}\nmissed {pose:?}\nin {mine:?}"
            );
            compared += 1;
            tangential += usize::from(pose.tangential);
        }
        for pose in mine.iter() {
            assert!(
                has_near(&general, pose),
                "{case}: {contacts:?} {locs:?}\nextra {pose:?}\nnot in {general:?}"
            );
        }
    }
    println!("{compared} poses compared, {tangential} tangential");
    assert!(
        compared > 20000 && tangential > 0,
        "{compared} {tangential}"
    );
}

/// A locator on the continuation of a slot's wall touches the end circle
/// at the smooth joint exactly: the closed form puts it there to within
/// rounding (the elimination landed up to 4e-8 off, enough to count as
/// inside the arc's segment), with the other two on the walls.
#[test]
fn slot_end_tangency_is_exact() {
    let h = 0.25;
    let lines = [
        Line {
            n: v2(0.0, -1.0),
            c: h,
        },
        Line {
            n: v2(0.0, 1.0),
            c: h,
        },
    ];
    let circle = Circle {
        centre: v2(0.1, 0.0),
        radius: h,
    };
    // Part turned by a quarter: the walls are vertical on the plate.
    let locs = [v2(2.0, 3.0), v2(1.5, 1.0), v2(2.0, 7.0)];
    let contacts = with_circle_at(2, lines, circle);
    let poses = solve_contact_poses(&contacts, &locs);
    let joint = poses
        .iter()
        .find(|p| p.tangential)
        .expect("a tangential pose");
    let p = rot_t(joint.pose.cos, joint.pose.sin, locs[2]) - joint.w;
    let want = circle.centre + v2(0.0, if p.y > 0.0 { h } else { -h });
    assert!((p - want).norm() <= 1e-14, "{p:?} vs {want:?}");
}

/// What `polished` reuses of Newton's last iterate is what it computed
/// before: the largest residual and the scaled Jacobian determinant from
/// [`system`]'s residuals and rows are those of `max_residual` and
/// `scaled_jacobian_det` to the bit (a locator at a circle's centre, a zero
/// row, included).
#[test]
fn reused_residuals_and_determinant_are_the_recomputed_ones() {
    let mut state = 0x51a7_c3e9_0d24_8b6fu64;
    for case in 0..3000 {
        let (mut contacts, locs) = random_contacts(&mut state, case % 4);
        let theta = TAU * rnd(&mut state);
        let (c, s) = cos_sin(theta);
        let mut w = v2(6.0 * rnd(&mut state) - 3.0, 6.0 * rnd(&mut state) - 3.0);
        if case % 7 == 0 {
            // The last locator exactly at its circle's centre.
            if let Contact::Circle(circle) = &mut contacts[2] {
                w = rot_t(c, s, locs[2]) - circle.centre;
            }
        }
        let (f, j) = system(&contacts, &locs, (c, s), w);
        let res = max_residual(&contacts, &locs, c, s, w);
        assert_eq!(largest_abs(&f).to_bits(), res.to_bits(), "{case}");
        let det = scaled_jacobian_det(&contacts, &locs, c, s, w);
        assert_eq!(scaled_det(&j).to_bits(), det.to_bits(), "{case}");
    }
}
