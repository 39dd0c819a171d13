//! The lane kernels (`lanes/`) against the scalar kernels (`contact_solver.rs`) on random
//! blocks of the random constraints of `kernels.rs`, bit for bit.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::Real;

use super::kernels::random_case;
use crate::{
    BodyState, Contact, ContactConstraint, Mat3, PassContext, restitution_contact, solve_contact,
    warm_start_contact,
};

/// Every bit of `states` and of each contact's stored impulses, for comparing two kernels.
fn bits_of(states: &[BodyState], contacts: &[Contact]) -> Vec<u32> {
    let mut bits = Vec::new();
    for s in states {
        let q = s.delta_rotation.quaternion();
        let values = s
            .linear_velocity
            .iter()
            .chain(s.angular_velocity.iter())
            .chain(s.delta_position.iter())
            .chain([&q.i, &q.j, &q.k, &q.w]);
        bits.extend(values.map(|v| v.to_bits()));
    }
    for c in contacts {
        for (p, total) in c.impulses.iter().zip(&c.total_normal_impulse) {
            bits.push(p.normal.to_bits());
            bits.extend(p.friction.iter().map(|v| v.to_bits()));
            bits.push(total.to_bits());
        }
        bits.extend(c.tilt_impulse.iter().map(|v| v.to_bits()));
    }
    bits
}

/// The lane kernels (`lanes.rs`) against the scalar kernels on random blocks of one to
/// [`crate::LANES`] of the random constraints above (any point count, friction zero or not,
/// restitution or none, patches and edges, fixed and kinematic sides, biased and relax
/// passes), through warm start, two solve passes and restitution: every bit of every body
/// state and stored impulse must agree, on AVX2 when the processor has it and on the
/// portable path. The step-level test (`tests/tests/solver_kernels.rs`) reaches these
/// branches through scenes; this one reaches combinations no scene lines up in one block.
#[test]
fn lane_kernels_give_the_scalar_kernels_bits_on_random_blocks() {
    use crate::lanes::{LANES, LaneBlock};
    use crate::sweep::Isa;

    let mut rng = ChaCha8Rng::seed_from_u64(0x1a9e5);
    for trial in 0..3_000 {
        let len = rng.random_range(1..=LANES);
        let mut constraints = Vec::new();
        let mut states = Vec::new();
        let mut passes = Vec::new();
        for l in 0..len {
            let (mut c, a, b, pass, threshold) = random_case(&mut rng).parts();
            c.body_a = (2 * l) as u32;
            c.body_b = (2 * l + 1) as u32;
            c.contact = l as u32;
            constraints.push(c);
            states.extend([a, b]);
            passes.push((pass, threshold));
        }
        // The lanes gather each body's inverse inertia: each lane has two bodies of its own,
        // whose inertias are its constraint's.
        let inertia: Vec<Mat3> = constraints
            .iter()
            .flat_map(|c| [c.inverse_inertia_a, c.inverse_inertia_b])
            .collect();
        // One block shares its pass settings: the first lane's.
        let (pass, threshold) = passes[0];
        let relax = PassContext {
            use_bias: false,
            friction: true,
            ..pass
        };

        // Scalar: one constraint at a time, the dynamic sides written back.
        let mut scalar_states = states.clone();
        let mut scalar_constraints = constraints.clone();
        let visit =
            |states: &mut [BodyState],
             cs: &mut [ContactConstraint],
             f: &dyn Fn(&mut ContactConstraint, &mut BodyState, &mut BodyState)| {
                for c in cs.iter_mut() {
                    let (ia, ib) = (c.body_a as usize, c.body_b as usize);
                    let (mut a, mut b) = (states[ia], states[ib]);
                    f(c, &mut a, &mut b);
                    if c.dynamic_a {
                        states[ia] = a;
                    }
                    if c.dynamic_b {
                        states[ib] = b;
                    }
                }
            };
        visit(&mut scalar_states, &mut scalar_constraints, &|c, a, b| {
            warm_start_contact(c, a, b)
        });
        visit(&mut scalar_states, &mut scalar_constraints, &|c, a, b| {
            solve_contact(c, a, b, &pass)
        });
        visit(&mut scalar_states, &mut scalar_constraints, &|c, a, b| {
            solve_contact(c, a, b, &relax)
        });
        visit(&mut scalar_states, &mut scalar_constraints, &|c, a, b| {
            restitution_contact(c, a, b, threshold)
        });
        let mut scalar_contacts = vec![Contact::default(); len];
        for c in &scalar_constraints {
            c.store_impulses(&mut scalar_contacts[c.contact as usize]);
        }
        let expected = bits_of(&scalar_states, &scalar_contacts);

        for avx2 in [false, Isa::detect() == Isa::Avx2] {
            let mut block = LaneBlock::default();
            block.start(len);
            for (l, c) in constraints.iter().enumerate() {
                block.set(l, c);
            }
            let mut lane_states = states.clone();
            if !avx2 {
                lane_passes::<false>(&mut block, &mut lane_states, &inertia, &pass, threshold);
            }
            #[cfg(target_arch = "x86_64")]
            if avx2 {
                // SAFETY: AVX2 was detected.
                unsafe {
                    lane_passes_avx2(&mut block, &mut lane_states, &inertia, &pass, threshold)
                };
            }
            let mut lane_contacts = vec![Contact::default(); len];
            block.store(&mut lane_contacts);
            let got = bits_of(&lane_states, &lane_contacts);
            let first = expected.iter().zip(&got).position(|(a, b)| a != b);
            assert!(
                first.is_none(),
                "trial {trial}: {len} lanes differ from the scalar kernels at value {}",
                first.unwrap_or(0)
            );
        }
    }
}

/// Warm start, a biased and a relax solve pass and restitution on one lane block, each pass
/// gathering the block's bodies from `states` and scattering the dynamic ones back, as the
/// solve does.
/// With `AVX2` (only inside [`lane_passes_avx2`]) the bodies are gathered as the solve's AVX2
/// path gathers them, with `LaneBlock::gather_avx2`.
#[inline(always)]
fn lane_passes<const AVX2: bool>(
    block: &mut crate::lanes::LaneBlock,
    states: &mut [BodyState],
    inverse_inertia: &[Mat3],
    pass: &PassContext,
    threshold: Real,
) {
    use crate::lanes::{self, LaneBlock, LaneBodies};
    let relax = PassContext {
        use_bias: false,
        friction: true,
        ..*pass
    };
    let mut run = |block: &mut LaneBlock, f: &dyn Fn(&mut LaneBlock, &mut LaneBodies)| {
        let n = states.len();
        assert_eq!(inverse_inertia.len(), n);
        // SAFETY: one thread; `gather` checks every body index against `n`, the length of
        // both arrays.
        unsafe {
            #[cfg(target_arch = "x86_64")]
            let mut v = if AVX2 {
                block.gather_avx2(states.as_ptr(), inverse_inertia.as_ptr(), n)
            } else {
                block.gather(states.as_ptr(), inverse_inertia.as_ptr(), n)
            };
            #[cfg(not(target_arch = "x86_64"))]
            let mut v = block.gather(states.as_ptr(), inverse_inertia.as_ptr(), n);
            f(block, &mut v);
            block.scatter(&v, states.as_mut_ptr());
        }
    };
    run(block, &|c, v| lanes::warm_start(c, v));
    run(block, &|c, v| lanes::solve(c, v, pass));
    run(block, &|c, v| lanes::solve(c, v, &relax));
    run(block, &|c, v| lanes::restitution(c, v, threshold));
}

/// [`lane_passes`] compiled for AVX2, as the solve's AVX2 path is.
///
/// # Safety
/// The processor runs AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn lane_passes_avx2(
    block: &mut crate::lanes::LaneBlock,
    states: &mut [BodyState],
    inverse_inertia: &[Mat3],
    pass: &PassContext,
    threshold: Real,
) {
    lane_passes::<true>(block, states, inverse_inertia, pass, threshold);
}

/// `LaneBlock::prepare` (each point's rows for eight lanes at once) against the reference
/// fill, `start` and `set` of each constraint `prepare_contact` builds, on random blocks of
/// one to eight random contacts: every value the kernels read of every lane must have the same
/// bits, on AVX2 when the processor has it and on the portable path, with and without warm
/// starting and the friction effect. The block is reused from trial to trial, so a full block
/// starts with the last trial's values in it, as a kept block does from step to step.
#[test]
fn lane_prepare_gives_the_scalar_prepare_bits() {
    use super::kernels::{PrepareInputs, random_prepare_inputs};
    use crate::lanes::{LANES, LaneBlock, PrepareSource};
    use crate::sweep::Isa;
    use crate::{Body, PrepareContext, prepare_contact};

    let mut rng = ChaCha8Rng::seed_from_u64(0x9e9a4e);
    let mut kept = [LaneBlock::default(), LaneBlock::default()];
    for trial in 0..3_000 {
        let len = rng.random_range(1..=LANES);
        let (mut bodies, mut states, mut contacts) = (Vec::new(), Vec::new(), Vec::new());
        let mut ctx: Option<PrepareContext> = None;
        for l in 0..len {
            let PrepareInputs {
                bodies: pair,
                states: pair_states,
                mut contact,
                ctx: c,
                ..
            } = random_prepare_inputs(&mut rng);
            // One block's lanes share the step's values: the first lane's.
            ctx.get_or_insert(c);
            contact.body_a = (2 * l) as u32;
            contact.body_b = (2 * l + 1) as u32;
            bodies.extend(pair);
            states.extend(pair_states);
            contacts.push(contact);
        }
        let mut ctx = ctx.expect("at least one lane");
        ctx.warm_start_scale = if rng.random_bool(0.8) { 1.0 } else { 0.0 };
        let friction = rng.random_bool(0.8);
        let inertia: Vec<Mat3> = bodies.iter().map(Body::inverse_inertia_world).collect();
        // The lanes in a shuffled contact order, as a color's order is.
        let mut indices: Vec<u32> = (0..len as u32).collect();
        for i in (1..len).rev() {
            indices.swap(i, rng.random_range(0..=i));
        }

        let mut expected = LaneBlock::default();
        expected.start(len);
        for (l, &i) in indices.iter().enumerate() {
            let mut c = prepare_contact(&bodies, &inertia, &states, &contacts, i as usize, &ctx);
            if !friction {
                // What the solve stage does to a scalar constraint with friction off.
                c.friction = 0.0;
                for p in &mut c.points {
                    p.tangent_impulse = [0.0; 2];
                }
            }
            expected.set(l, &c);
        }
        let source = PrepareSource {
            bodies: &bodies,
            inverse_inertia: &inertia,
            states: &states,
            contacts: &contacts,
            ctx: &ctx,
            friction,
        };
        for (block, isa) in kept.iter_mut().zip([Isa::Portable, Isa::detect()]) {
            block.prepare(&indices, &source, isa);
            for l in 0..len {
                let (want, got) = (expected.lane_bits(l), block.lane_bits(l));
                let first = want.iter().zip(&got).position(|(a, b)| a != b);
                assert!(
                    first.is_none() && want.len() == got.len(),
                    "trial {trial}, {isa:?}: lane {l} of {len} differs from the reference fill at value {first:?}"
                );
            }
        }
    }
}

/// `LaneBlock::gather_avx2` (each body's state and inverse inertia loaded as rows of eight
/// floats and transposed into lanes by shuffles) against `LaneBlock::gather` (one float at a
/// time): every gathered value must have the same bits. The matrices are random and not
/// symmetric, so a row taken for a column shows, and the bodies include the last of the
/// arrays (whose loads end exactly at the array's end) and repeats, as fixed bodies and
/// padding lanes repeat.
#[cfg(target_arch = "x86_64")]
#[test]
fn avx2_gather_gives_the_scalar_gathers_bits() {
    use crate::lanes::{LANES, LaneBlock, LaneBodies};
    use crate::sweep::Isa;
    use tumble_geometry::{Rot, Vec3};

    /// The AVX2 gather inside a function compiled for AVX2, as the solve calls it.
    ///
    /// # Safety
    /// The processor runs AVX2; the arrays hold `n` elements and the block's bodies are
    /// below `n`.
    #[target_feature(enable = "avx2")]
    unsafe fn gather_avx2(block: &LaneBlock, s: &[BodyState], m: &[Mat3]) -> LaneBodies {
        assert_eq!(s.len(), m.len());
        // SAFETY: the caller's contract.
        unsafe { block.gather_avx2(s.as_ptr(), m.as_ptr(), s.len()) }
    }

    if Isa::detect() != Isa::Avx2 {
        eprintln!("skipped: the processor has no AVX2");
        return;
    }
    let mut rng = ChaCha8Rng::seed_from_u64(0x6a7e);
    let value = |rng: &mut ChaCha8Rng| rng.random_range(-10.0..10.0) as Real;
    for trial in 0..500 {
        let n = rng.random_range(1..40);
        let states: Vec<BodyState> = (0..n)
            .map(|_| BodyState {
                linear_velocity: Vec3::from_fn(|_, _| value(&mut rng)),
                angular_velocity: Vec3::from_fn(|_, _| value(&mut rng)),
                delta_position: Vec3::from_fn(|_, _| value(&mut rng)),
                delta_rotation: Rot::from_scaled_axis(Vec3::from_fn(|_, _| value(&mut rng))),
            })
            .collect();
        let inertia: Vec<Mat3> = (0..n)
            .map(|_| Mat3::from_fn(|_, _| value(&mut rng)))
            .collect();
        let len = rng.random_range(1..=LANES);
        let (mut c, ..) = random_case(&mut rng).parts();
        let mut block = LaneBlock::default();
        block.start(len);
        for l in 0..len {
            // The last body in every trial's first lane: its loads end at the arrays' ends.
            c.body_a = if l == 0 {
                (n - 1) as u32
            } else {
                rng.random_range(0..n) as u32
            };
            c.body_b = rng.random_range(0..n) as u32;
            block.set(l, &c);
        }
        // SAFETY: AVX2 was detected; the bodies are below `n`.
        let fast = unsafe { gather_avx2(&block, &states, &inertia) };
        // SAFETY: the bodies are below `n`, the length of both arrays.
        let slow = unsafe { block.gather(states.as_ptr(), inertia.as_ptr(), n) };
        assert_eq!(
            fast.bits(),
            slow.bits(),
            "trial {trial}: the gathers differ"
        );
    }
}
