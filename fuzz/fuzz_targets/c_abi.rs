//! Any bytes through the C ABI's readers (a URDF string, a contour table), then a controller
//! and a step at arbitrary numbers: a status and a message, never a panic across the boundary
//! or a leak (every handle made is destroyed).
#![no_main]

use libfuzzer_sys::fuzz_target;
use pvfc_c::*;
use std::ffi::CString;
use std::ptr::{null, null_mut};

const UR5: &str = include_str!("../../models/ur5/ur5_robot.urdf");

fuzz_target!(|data: (&str, &str, [f64; 6], f64)| {
    let (urdf_or_contour, contour, q, dt) = data;
    let (Ok(a), Ok(b)) = (CString::new(urdf_or_contour), CString::new(contour)) else {
        return;
    };
    let ur5 = CString::new(UR5).unwrap_or_default();
    // SAFETY: valid NUL-terminated strings, out pointers, arrays of 6; every handle made is
    // destroyed once.
    unsafe {
        let mut robot = null_mut();
        let _ =
            pvfc_robot_from_urdf_string(a.as_ptr(), c"f.urdf".as_ptr(), null(), null(), &mut robot);
        pvfc_robot_destroy(robot);
        let mut robot = null_mut();
        if pvfc_robot_from_urdf_string(
            ur5.as_ptr(),
            c"ur5.urdf".as_ptr(),
            c"tool0".as_ptr(),
            null(),
            &mut robot,
        ) != pvfc_status::PVFC_OK
        {
            return;
        }
        let mut c = null_mut();
        if pvfc_contour_toml(b.as_ptr(), null(), &mut c) == pvfc_status::PVFC_OK {
            let s = pvfc_settings_default();
            let mut ctl = null_mut();
            if pvfc_controller_new(robot, c, null(), 0, &s, &mut ctl) == pvfc_status::PVFC_OK {
                let mut torque = [0.0; 6];
                let v = [0.0; 6];
                let _ = pvfc_controller_step(
                    ctl,
                    q.as_ptr(),
                    v.as_ptr(),
                    6,
                    dt,
                    torque.as_mut_ptr(),
                    6,
                    null_mut(),
                );
                pvfc_controller_destroy(ctl);
            }
            pvfc_contour_destroy(c);
        }
        pvfc_robot_destroy(robot);
    }
});
