use super::*;

#[test]
fn segment_cells_and_offsets() {
    let b = place(
        &Shape::Segment {
            from: -0.005,
            to: 0.0,
        },
        5e-5,
        7850.0,
        false,
    );
    assert_eq!(b.positions.len(), 100);
    assert!((b.positions[0].x - (-0.005 + 2.5e-5)).abs() < 1e-15);
    assert!((b.offsets[99] - 2.5e-5).abs() < 1e-15);
    let m: f64 = b.masses.iter().sum();
    assert!((m - 7850.0 * 0.005).abs() < 1e-9);
}

/// The jitter moves each particle by at most `fraction·Δx` per axis,
/// actually uses the range (not a constant shift), keeps the masses and
/// the order along a segment, recomputes the surface offsets from the
/// moved centres, and repeats exactly for one seed (another seed gives
/// other positions).
#[test]
fn jitter_bounds_offsets_and_determinism() {
    let shape = Shape::Segment {
        from: -0.005,
        to: 0.0,
    };
    let regular = place(&shape, 5e-5, 7850.0, false);
    let jittered = |seed| {
        let mut b = place(&shape, 5e-5, 7850.0, false);
        jitter(&mut b, &shape, 0.1, seed, false);
        b
    };
    let a = jittered(3);
    let d: Vec<f64> = a
        .positions
        .iter()
        .zip(&regular.positions)
        .map(|(p, q)| (p.x - q.x) / regular.spacing)
        .collect();
    assert!(d.iter().all(|x| x.abs() <= 0.1));
    let (lo, hi) = d
        .iter()
        .fold((0.0f64, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    assert!(lo < -0.08 && hi > 0.08, "range used: {lo} .. {hi}");
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    assert!(mean.abs() < 0.02, "no systematic shift: {mean}");
    assert_eq!(a.masses, regular.masses);
    assert!(a.positions.windows(2).all(|w| w[1].x > w[0].x));
    for (p, o) in a.positions.iter().zip(&a.offsets) {
        assert_eq!(*o, (p.x + 0.005).min(-p.x));
    }
    assert_eq!(a.positions, jittered(3).positions);
    assert_ne!(a.positions, jittered(4).positions);

    // 2-D: both axes move; a particle pushed past a curved surface gets
    // offset 0, never a negative one.
    let disk = Shape::Disk {
        center: vec![0.0, 0.0],
        radius: 5e-3,
        lattice: Lattice::Square,
    };
    let regular = place(&disk, 2.5e-4, 7850.0, false);
    let mut b = place(&disk, 2.5e-4, 7850.0, false);
    jitter(&mut b, &disk, 0.3, 1, false);
    let moved = |f: fn(DVec2) -> f64| {
        b.positions
            .iter()
            .zip(&regular.positions)
            .any(|(p, q)| f(*p - *q).abs() > 0.2 * 2.5e-4)
    };
    assert!(moved(|d| d.x) && moved(|d| d.y));
    assert!(b.offsets.iter().all(|&o| o >= 0.0));
}

#[test]
fn disk_mass_both_lattices() {
    for lattice in [Lattice::Square, Lattice::Polar] {
        let b = place(
            &Shape::Disk {
                center: vec![0.0, 0.0],
                radius: 5e-3,
                lattice,
            },
            2.5e-4,
            7850.0,
            false,
        );
        let m: f64 = b.masses.iter().sum();
        let exact = 7850.0 * PI * 25e-6;
        // The polar lattice has the exact area; the square one up to its staircase.
        let tol = if lattice == Lattice::Polar {
            1e-12
        } else {
            0.02
        };
        assert!((m / exact - 1.0).abs() < tol, "{lattice:?}: {m} vs {exact}");
        assert!(b.offsets.iter().all(|&o| o > 0.0 && o <= 5e-3));
    }
}

/// A ring centred on the axis of a body of revolution (a hollow
/// sphere): every half ring, the innermost too, is filled at the
/// lattice's spacing, and the masses are the shell's (a disk's
/// innermost half ring alone holds a single particle).
#[test]
fn hollow_sphere_half_rings_are_filled() {
    let (r_in, r_out, dx) = (0.08, 0.1, 2e-3);
    let b = place(
        &Shape::Ring {
            center: vec![0.0, 0.0],
            inner_radius: r_in,
            outer_radius: r_out,
            lattice: Lattice::Polar,
        },
        dx,
        1845.0,
        true,
    );
    for k in 0..10 {
        let r = r_in + (k as f64 + 0.5) * dx;
        let ring: Vec<DVec2> = b
            .positions
            .iter()
            .copied()
            .filter(|p| (p.length() - r).abs() < 1e-9)
            .collect();
        assert_eq!(ring.len(), (PI * r / dx).round() as usize, "ring {k}");
        assert!(ring.iter().all(|p| p.x > 0.0));
    }
    let m: f64 = b.masses.iter().sum();
    let half = 1845.0 * 0.5 * PI * (r_out * r_out - r_in * r_in);
    assert!((m / half - 1.0).abs() < 1e-12, "{m} vs {half}");
}

/// A polar disk centred on a symmetry plane is the whole disk cut: the
/// whole lattice's particles on the modelled side, those on the plane put
/// exactly on it with half their mass, and half the disk's mass in all.
#[test]
fn polar_disk_on_a_symmetry_plane_is_the_whole_disk_cut() {
    let (c, r, dx, rho) = ([0.003, -0.002], 0.005, 2e-4, 7850.0);
    let disk = Shape::Disk {
        center: c.to_vec(),
        radius: r,
        lattice: Lattice::Polar,
    };
    let plane = crate::scene::Symmetry {
        normal: vec![0.0, -1.0],
        point: vec![0.0, c[1]],
    };
    let whole = place(&disk, dx, rho, false);
    let mut b = whole.clone();
    cut(&mut b, &plane);
    let tol = 1e-9 * dx;
    let kept: Vec<usize> = (0..whole.positions.len())
        .filter(|&k| plane.side(whole.positions[k]) >= -tol)
        .collect();
    assert_eq!(b.positions.len(), kept.len());
    let mut on = 0;
    for (k, (p, m)) in kept.iter().zip(b.positions.iter().zip(&b.masses)) {
        let (q, mq) = (whole.positions[*k], whole.masses[*k]);
        if plane.side(q).abs() <= tol {
            on += 1;
            assert_eq!(p.y, c[1], "{q} not put on the plane");
            assert_eq!(p.x, q.x);
            assert_eq!(*m, 0.5 * mq);
        } else {
            assert!(plane.side(*p) > 0.1 * dx, "{p} lies near the plane");
            assert_eq!((*p, *m), (q, mq));
        }
    }
    // The centre and the rings' particles on the diameter.
    assert!(on > (r / dx) as usize, "{on} particles on the plane");
    let m: f64 = b.masses.iter().sum();
    let half = 0.5 * whole.masses.iter().sum::<f64>();
    assert!((m / half - 1.0).abs() < 1e-12, "{m} vs {half}");
}
