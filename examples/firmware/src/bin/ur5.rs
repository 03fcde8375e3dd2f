//! The 6-joint f32 control step on the target: the UR5 (constants of `src/ur5.rs`) following a
//! closed joint-space contour with gravity compensation, 1,000 steps at 1 kHz against the
//! chain's own dynamics integrated on the target (semi-implicit Euler, 4 substeps). For the
//! instruction count (`scripts/firmware_instructions.py --symbol pvfc_arm_step`); prints the
//! navigation function at the start and the end, exits 0 if it fell and nothing faulted.
#![no_std]
#![no_main]

#[path = "../ur5.rs"]
mod ur5;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use panic_halt as _;
use pvfc_core::mechanics::{ChainJoint, Pose, RigidInertia};
use pvfc_core::nalgebra::{Matrix3, SVector, Vector3};
use pvfc_core::prelude::*;

/// The arm's controller type.
type Arm = Controller<
    f32,
    JointSpace<f32, 6>,
    SerialChain<f32, 6>,
    SuspendedField<
        f32,
        JointSpace<f32, 6>,
        PeriodicBSpline<f32, JointSpace<f32, 6>, 6, 8>,
        JointNavigation<f32, 6>,
        ExponentialPacing<f32>,
        6,
    >,
    6,
>;

const WAYPOINTS: [[f32; 6]; 5] = [
    [0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
    [0.5, -1.0, 1.2, -1.7, -1.4, 0.3],
    [0.8, -1.4, 1.6, -1.6, -1.2, 0.6],
    [0.3, -1.7, 1.9, -1.9, -1.5, 0.2],
    [-0.3, -1.5, 1.7, -2.0, -1.8, -0.3],
];

fn m3(m: &[[f64; 3]; 3]) -> Matrix3<f32> {
    Matrix3::from_fn(|i, j| m[i][j] as f32)
}

fn v3(v: &[f64; 3]) -> Vector3<f32> {
    Vector3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

fn build() -> Result<(SerialChain<f32, 6>, Arm), Error> {
    let joints = ur5::JOINTS.map(|(r, t, a)| ChainJoint {
        kind: JointKind::Circular,
        origin: Pose {
            rotation: m3(&r),
            translation: v3(&t),
        },
        axis: v3(&a),
    });
    let links = ur5::LINKS.map(|(m, c, i)| RigidInertia {
        mass: m as f32,
        com: v3(&c),
        inertia: m3(&i),
    });
    let chain = SerialChain::new(joints, links)?.with_tool(Pose {
        rotation: m3(&ur5::TOOL.0),
        translation: v3(&ur5::TOOL.1),
    })?;
    let kinds = chain.kinds();
    let pts = WAYPOINTS.map(|w| JointSpace::new(SVector::from(w), kinds));
    let field = SuspendedField::new(
        PeriodicBSpline::through_slice(&pts, 1.0)?,
        JointNavigation::new(SVector::repeat(4.0), kinds)?,
        ExponentialPacing::new(50.0)?,
    );
    let law = PvfcLaw::new(chain, field, Flywheel::new(1.0, 40.0)?, 1.0)?;
    Ok((
        chain,
        Controller::new(law)
            .starting_at_rest(0.0)
            .with_gravity_compensation(),
    ))
}

/// One 6-joint control step, out of line for the instruction count.
#[no_mangle]
#[inline(never)]
fn pvfc_arm_step(
    ctl: &mut Arm,
    q: &JointSpace<f32, 6>,
    v: &SVector<f32, 6>,
) -> Result<StepOutput<f32, 6>, Error> {
    ctl.step(q, v, 1e-3)
}

#[entry]
fn main() -> ! {
    let code = match run() {
        Ok((u0, u1)) if u1 < u0 => {
            hprintln!(
                "pvfc ur5: U {} -> {} (1e-6), no fault",
                (u0 * 1e6) as i32,
                (u1 * 1e6) as i32
            );
            debug::EXIT_SUCCESS
        }
        Ok((u0, u1)) => {
            hprintln!(
                "pvfc ur5: U did not fall: {} -> {} (1e-6)",
                (u0 * 1e6) as i32,
                (u1 * 1e6) as i32
            );
            debug::EXIT_FAILURE
        }
        Err(e) => {
            hprintln!("pvfc ur5: FAULT: {}", e.kind().as_str());
            debug::EXIT_FAILURE
        }
    };
    debug::exit(code);
    loop {
        cortex_m::asm::wfi();
    }
}

fn run() -> Result<(f32, f32), Error> {
    let (chain, mut ctl) = build()?;
    let kinds = chain.kinds();
    let mut q = SVector::from(WAYPOINTS[0]).add_scalar(0.2);
    let mut v = SVector::<f32, 6>::zeros();
    let (mut u0, mut u1) = (f32::NAN, f32::NAN);
    for k in 0..1000 {
        let x = JointSpace::new(q, kinds);
        let out = pvfc_arm_step(&mut ctl, &x, &v)?;
        if k == 0 {
            u0 = out.diagnostics.potential;
        }
        u1 = out.diagnostics.potential;
        for _ in 0..4 {
            let a = chain.acceleration(&JointSpace::new(q, kinds), &v, &out.torque)?;
            v += a * 2.5e-4;
            q += v * 2.5e-4;
        }
    }
    Ok((u0, u1))
}
