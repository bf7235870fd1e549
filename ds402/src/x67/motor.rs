//! The simulated motor, encoder and load behind one X67SM2436 axis.
//!
//! Nothing in the seed describes a motor; this is the harness that lets the axis model and the node exercise
//! every path: a two-phase stepper with a winding inductance and resistance (for the motor identification,
//! X67-18.11.3.7-01), a rotor that follows the internal counter unless it is blocked or wired in reverse, an
//! optional ABR incremental encoder on the shaft (X67-3-08, X67-3-09), a mechanical load that sets the load value
//! 0…7 (X67-18.6.1.1-03) and injectable faults (open or shorted winding, output-stage over-temperature).
//!
//! Units: rotor positions in microsteps (1/256 full step, X67-3-05), speeds in microsteps/second.

/// Microsteps per full step (X67-3-05).
pub const MICROSTEPS_PER_STEP: i64 = 256;

/// Motor identification value for an invalid result (overflow), X67-18.11.3.7-03.
pub const IDENT_OVERFLOW: u16 = 65_534;

/// Largest valid motor identification value in µs (X67-18.11.3.7-03).
pub const IDENT_MAX_US: f64 = 32_767.0;

/// The electrical and mechanical data of a simulated motor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotorParams {
    /// Full steps per revolution (200 for a 1.8° motor).
    pub steps_per_rev: u32,
    /// Winding inductance in millihenry.
    pub inductance_mh: f64,
    /// Winding resistance in ohm.
    pub resistance_ohm: f64,
    /// The motor is wired the wrong way round: the rotor turns against the commanded direction.
    pub reversed: bool,
    /// The speed in microsteps/second above which the back-EMF keeps the commanded current out of the windings
    /// under load (X67-18.6.3.1-03); without load the limit is 5 % lower.
    pub back_emf_limit: i64,
    /// The moment of inertia of the rotor and what turns with it, in kg·m². Its kinetic energy goes back
    /// into the DC bus when the voltage is switched off on a turning motor (18.11.4.3, see
    /// [`Motor::regenerated_joules`]).
    pub inertia_kg_m2: f64,
}

impl Default for MotorParams {
    /// A 1.8° motor with 3 mH and 1.5 Ω per winding, a back-EMF limit of 400 000 microsteps/s (about 7.8
    /// revolutions per second) and 0.3 kg·cm² of rotor inertia (3 × 10⁻⁵ kg·m², a NEMA 23 motor's).
    fn default() -> Self {
        MotorParams {
            steps_per_rev: 200,
            inductance_mh: 3.0,
            resistance_ohm: 1.5,
            reversed: false,
            back_emf_limit: 400_000,
            inertia_kg_m2: 3.0e-5,
        }
    }
}

/// Faults the harness can inject into a motor and its output stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Faults {
    /// A winding is open: current error 0xFF00 (with control-word bit 13) and open circuit 0xFF11
    /// (X67-18.6.3.1-03, X67-18.11.3.13-09); the identification overflows.
    pub open_winding: bool,
    /// A winding is shorted: twice the motor current flows, overcurrent 0x2300 (X67-18.6.3.1-04).
    pub short: bool,
    /// The output stage of this axis is over its temperature limit: 0x4200 on this axis only
    /// (X67-18.6.3.1-02).
    pub output_stage_overtemperature: bool,
    /// The rotor is blocked: it does not turn whatever the internal counter does (X67-18.6.3.3-01), and the
    /// load value is 0.
    pub blocked: bool,
}

/// The mechanical load on the shaft.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Load {
    /// A load torque in percent of the motor's holding torque; the load value follows
    /// [`load_value`].
    Torque(u8),
    /// The load value 0…7 forced directly (values above 7 act as 7).
    Value(u8),
}

impl Default for Load {
    fn default() -> Self {
        Load::Torque(0)
    }
}

/// The load value 0…7 of the stall detection for a rotor turning at `speed` microsteps/second against
/// `torque` percent: higher speed gives higher values, more load lower ones (X67-18.6.1.1-03). The model is
/// `2 + min(|speed| / 4000, 5) − torque / 20`, clamped to 0…7.
pub fn load_value(speed: i64, torque: u8) -> u8 {
    let v = 2 + (speed.unsigned_abs() / 4000).min(5) as i64 - i64::from(torque / 20);
    v.clamp(0, 7) as u8
}

/// The motor-identification value in µs for 1 A of current rise (X67-18.11.3.7-01): the winding current
/// `i(t) = V/R · (1 − e^(−t·R/L))` is measured from a third of the nominal current up to the nominal
/// current (X67-18.11.3.7-06) and the time is scaled to 1 A.
///
/// Returns `None` when no valid result can be produced because that range spans less than 1 A (the
/// catalogue's pick: the register keeps its value), and [`IDENT_OVERFLOW`] when the nominal current is never
/// reached (open winding, too little voltage) or the time exceeds 32 767 µs.
pub fn identification_us(
    params: &MotorParams,
    open: bool,
    supply_volts: f64,
    nominal_ma: u32,
) -> Option<u16> {
    let i_nom = f64::from(nominal_ma) / 1000.0;
    if i_nom * 2.0 / 3.0 < 1.0 {
        return None;
    }
    let r = params.resistance_ohm;
    let l = params.inductance_mh / 1000.0;
    if open || !(r > 0.0 && l > 0.0 && supply_volts > 0.0) {
        return Some(IDENT_OVERFLOW);
    }
    // The current rises toward V/R: when that is not above the nominal current, the nominal current is
    // never reached and the time to it is not finite (the logarithm of 0 or less), an overflow below.
    let t = |i: f64| -(l / r) * (1.0 - i * r / supply_volts).ln();
    let per_amp_us = (t(i_nom) - t(i_nom / 3.0)) / (i_nom * 2.0 / 3.0) * 1e6;
    if !(per_amp_us.is_finite() && per_amp_us <= IDENT_MAX_US) {
        return Some(IDENT_OVERFLOW);
    }
    Some(per_amp_us.round().max(1.0) as u16)
}

/// A simulated motor: parameters, faults, load and the rotor position.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Motor {
    /// Electrical and mechanical data.
    pub params: MotorParams,
    /// Injected faults.
    pub faults: Faults,
    /// The load on the shaft.
    pub load: Load,
    /// Encoder lines per revolution of the ABR encoder on the shaft, or 0 for none. With an encoder the
    /// axis's A and B inputs (DI1/DI2 for axis 1, DI4/DI5 for axis 2) follow the shaft.
    pub encoder_lines: u32,
    rotor: i64,
}

impl Motor {
    /// The rotor position in microsteps (1/256 full step); one revolution is `steps_per_rev × 256`.
    pub const fn rotor(&self) -> i64 {
        self.rotor
    }

    /// The rotor angle in full steps (X67-3-05: 256 microsteps turn the rotor by one full step).
    pub fn full_steps(&self) -> f64 {
        self.rotor as f64 / MICROSTEPS_PER_STEP as f64
    }

    /// How far the rotor turns when the internal counter advances by `delta` with the motor powered: not at
    /// all when blocked, against the counter when wired in reverse.
    pub const fn rotor_delta(&self, delta: i64) -> i64 {
        if self.faults.blocked {
            0
        } else if self.params.reversed {
            -delta
        } else {
            delta
        }
    }

    /// Turns the rotor by `delta` microsteps.
    pub fn turn(&mut self, delta: i64) {
        self.rotor += delta;
    }

    /// The encoder's quadrature phase count at rotor position `rotor`: 4 counts per line (4x evaluation,
    /// X67-3-09), rounded toward −∞; 0 without an encoder.
    pub fn encoder_phase(&self, rotor: i64) -> i64 {
        if self.encoder_lines == 0 {
            return 0;
        }
        let per_rev =
            i128::from(self.params.steps_per_rev.max(1)) * i128::from(MICROSTEPS_PER_STEP);
        let counts = i128::from(rotor) * 4 * i128::from(self.encoder_lines);
        counts.div_euclid(per_rev) as i64
    }

    /// The load value 0…7 at `speed` microsteps/second: 0 with the rotor blocked, else from [`Load`].
    pub fn load_value(&self, speed: i64) -> u8 {
        if self.faults.blocked {
            return 0;
        }
        match self.load {
            Load::Value(v) => v.min(7),
            Load::Torque(t) => load_value(speed, t),
        }
    }

    /// The energy in J that a rotor turning at `speed` microsteps/second gives back when the motor voltage
    /// goes off (18.11.4.3, Operation enable → Switch on disabled: "regeneration on a motor running at no
    /// load"): its kinetic energy ½·J·ω², less the share a load torque takes while it coasts to a stop
    /// (`torque` percent of it); nothing from a blocked rotor.
    pub fn regenerated_joules(&self, speed: i64) -> f64 {
        if self.faults.blocked {
            return 0.0;
        }
        let per_rev = f64::from(self.params.steps_per_rev.max(1)) * MICROSTEPS_PER_STEP as f64;
        let omega = speed as f64 / per_rev * std::f64::consts::TAU;
        let kinetic = 0.5 * self.params.inertia_kg_m2 * omega * omega;
        let kept = match self.load {
            Load::Torque(t) => 1.0 - f64::from(t.min(100)) / 100.0,
            Load::Value(_) => 1.0,
        };
        kinetic * kept
    }

    /// Whether the back-EMF keeps the commanded current out of the windings at `speed` microsteps/second
    /// (X67-18.6.3.1-03): above the limit under load, 5 % below it without load.
    pub fn back_emf_exceeded(&self, speed: i64) -> bool {
        let unloaded = matches!(self.load, Load::Torque(0));
        let limit = if unloaded {
            self.params.back_emf_limit - self.params.back_emf_limit / 20
        } else {
            self.params.back_emf_limit
        };
        speed.abs() > limit
    }
}
