//! `PatternGenerator_sinusoidal`: φ_i(t) = A_i sin(2π f_i t + i·Δφ) + O_i
//! (thesis eq. 3.1, table 3.1), parameters uniform or per joint.

use crate::control::descriptor::{ModuleDescriptor, ParamDescriptor};

const PARAMETERS: &[ParamDescriptor] = &[
    ParamDescriptor {
        name: "Amplitude",
        aliases: &[],
        unit: "deg",
        default: 40.0,
        min: 0.0,
        max: 90.0,
        help: "amplitude A_i of the joint's sine",
    },
    ParamDescriptor {
        name: "Frequency",
        aliases: &[],
        unit: "Hz",
        default: 1.0,
        min: 0.0,
        max: 10.0,
        help: "frequency 1/T_i of the travelling wave",
    },
    ParamDescriptor {
        name: "Phase_Difference",
        aliases: &["Phase difference", "Phase"],
        unit: "deg",
        default: 55.0,
        min: -180.0,
        max: 180.0,
        help: "phase lag between neighbouring joints (its sign sets the direction)",
    },
    ParamDescriptor {
        name: "Offset",
        aliases: &[],
        unit: "deg",
        default: 0.0,
        min: -90.0,
        max: 90.0,
        help: "offset O_i added to the sine",
    },
];

pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "PatternGenerator_sinusoidal",
        summary: "sine travelling wave (eq. 3.1)",
        parameters: PARAMETERS,
        series: &["Angle", "Time", "Phase_Difference", "Frequency"],
        sensing: false,
    }
}
