//! `DirectJointAccess`: holds its joints at fixed angles (thesis listing B.5).

use crate::control::descriptor::{ModuleDescriptor, ParamDescriptor};

const PARAMETERS: &[ParamDescriptor] = &[ParamDescriptor {
    name: "Angle",
    aliases: &["Position", "Desired angle"],
    unit: "deg",
    default: 0.0,
    min: -90.0,
    max: 90.0,
    help: "angle the joint is held at",
}];

pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "DirectJointAccess",
        summary: "fixed joint angles",
        parameters: PARAMETERS,
        series: &["desired_angle"],
        sensing: false,
    }
}
