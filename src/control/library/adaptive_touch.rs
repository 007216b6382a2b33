//! `Global_Adaptive_Touch`: the sensor-driven offset module of the thesis's second
//! experiment (6.2, table 6.5). It watches all touch sensors, detects being stuck and
//! changes joint offsets at rates `Constant 1..8`, recovering the base shape at the
//! `Recovering` speed. The thesis's GA file (listing B.7) names two of the parameters
//! `Get-stuck-threshold` and `back to zero constant`; both spellings are accepted.

use crate::control::descriptor::{ModuleDescriptor, ParamDescriptor};

const fn constant(name: &'static str, help: &'static str) -> ParamDescriptor {
    ParamDescriptor {
        name,
        aliases: &[],
        unit: "deg/step",
        default: 0.5,
        min: 0.0,
        max: 100.0,
        help,
    }
}

const PARAMETERS: &[ParamDescriptor] = &[
    ParamDescriptor {
        name: "Get-stuck",
        aliases: &["Get-stuck-threshold", "Get stuck threshold"],
        unit: "steps",
        default: 300.0,
        min: 1.0,
        max: 100_000.0,
        help: "steps without progress after which the robot counts as stuck",
    },
    ParamDescriptor {
        name: "Recovering",
        aliases: &["back to zero constant", "Recovering speed"],
        unit: "deg/step",
        default: 0.1,
        min: 0.0,
        max: 10.0,
        help: "speed at which offsets return to the base shape",
    },
    constant("Constant 1", "offset increase rate, rule 1"),
    constant("Constant 2", "offset increase rate, rule 2"),
    constant("Constant 3", "offset increase rate, rule 3"),
    constant("Constant 4", "offset increase rate, rule 4"),
    constant("Constant 5", "offset decrease rate, rule 5"),
    constant("Constant 6", "offset decrease rate, rule 6"),
    constant("Constant 7", "offset decrease rate, rule 7"),
    constant("Constant 8", "offset decrease rate, rule 8"),
];

pub fn descriptor() -> ModuleDescriptor {
    ModuleDescriptor {
        type_name: "Global_Adaptive_Touch",
        summary: "touch-driven adaptive offsets (experiment 2)",
        parameters: PARAMETERS,
        series: &["desired_angle"],
        sensing: true,
    }
}
