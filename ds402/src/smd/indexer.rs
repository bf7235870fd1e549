//! The SMD23K-B / SMD24K indexer in Command Mode (seed 000, References 2 and 6), as a sans-IO model: each
//! call of [`Indexer::cycle`] is one process-data exchange — the unit takes the 20 output bytes, acts on
//! the 0→1 edges of the command bits, runs its motion for the cycle's time and answers with the 20 input
//! bytes. Configuration (`8010:01–07`) is written with [`Indexer::write_config`].
//!
//! Moves run on the profile maths of Reference 3 ([`super::profile`]): the position is the profile's
//! distance at the move's elapsed time, rounded to whole steps, and a move ends exactly on its target.
//! Motion status bits follow the phase the profile is in at the end of the cycle.
//!
//! In this model now: configuration validity (Configuration_Error, Position_Invalid on every write,
//! Enable_Driver refused while invalid); the command-acceptance rules (edges only, one CMD_word0 bit at a
//! time, parameter ranges, Absolute refused while Position_Invalid, moves refused while another runs or
//! the driver is disabled); Absolute and Relative moves, Hold and Resume, Immediate Stop, Preset Position
//! (also to the encoder), Preset Encoder, Reset Errors, the Motor_Current override of CMD_word1 bit 1;
//! STATUS_word0/1 with the 500 ms heartbeat, Command_Acknowledge and Move_Complete's rules; the encoder
//! counting with the motor. Not in it yet: homing, jog and registration moves, assembled and indexed
//! moves, the DC inputs, stall detection, idle current reduction, STO and temperature, EtherCAT states —
//! their command bits are refused with Command_Error.
//!
//! Choices where the manual is silent (catalogue picks unless said otherwise):
//! - Hold during the final deceleration of a move whose controlled stop would pass the target: the move
//!   simply completes (Move_Complete), there is nothing left to hold.
//! - A Hold's controlled stop decelerates from the present speed at the move's Deceleration and Jerk.
//! - A rejected command leaves Move_Complete as it was (SMD-R6-040 speaks of a move not yet complete).
//! - Preset Position with CMD_word1 bit 13 and the encoder disabled presets to 0 (Encoder_Position reads 0).

use std::time::Duration;

use super::config::{Configuration, EncoderKind, CFG0_USE_ENCODER};
use super::profile::{MoveParams, Phase, Profile};

/// STATUS_word0 bits (Reference 6, Figure R6.4).
pub mod stat0 {
    /// Bit 0.
    pub const MOVING_CW: u16 = 1 << 0;
    /// Bit 1.
    pub const MOVING_CCW: u16 = 1 << 1;
    /// Bit 2.
    pub const IN_HOLD_STATE: u16 = 1 << 2;
    /// Bit 3.
    pub const STOPPED: u16 = 1 << 3;
    /// Bit 4.
    pub const AT_HOME: u16 = 1 << 4;
    /// Bit 5.
    pub const ACCELERATING: u16 = 1 << 5;
    /// Bit 6.
    pub const DECELERATING: u16 = 1 << 6;
    /// Bit 7.
    pub const MOVE_COMPLETE: u16 = 1 << 7;
    /// Bit 8.
    pub const IN_ASSEMBLED_MODE: u16 = 1 << 8;
    /// Bit 9.
    pub const WAITING_FOR_SEGMENT: u16 = 1 << 9;
    /// Bit 10.
    pub const POSITION_INVALID: u16 = 1 << 10;
    /// Bit 11.
    pub const INPUT_ERROR: u16 = 1 << 11;
    /// Bit 12.
    pub const COMMAND_ERROR: u16 = 1 << 12;
    /// Bit 13.
    pub const CONFIGURATION_ERROR: u16 = 1 << 13;
    /// Bit 14.
    pub const MODULE_OK: u16 = 1 << 14;
    /// Bit 15.
    pub const MODE_FLAG: u16 = 1 << 15;
}

/// STATUS_word1 bits (Reference 6, Figure R6.5).
pub mod stat1 {
    /// Bit 0.
    pub const IN1_ACTIVE: u16 = 1 << 0;
    /// Bit 1.
    pub const IN2_ACTIVE: u16 = 1 << 1;
    /// Bit 4.
    pub const TEMPERATURE_ABOVE_90: u16 = 1 << 4;
    /// Bit 5.
    pub const PREOP_SAFEOP: u16 = 1 << 5;
    /// Bit 7.
    pub const DRIVER_FAULT: u16 = 1 << 7;
    /// Bit 9.
    pub const INVALID_JOG_CHANGE: u16 = 1 << 9;
    /// Bit 10.
    pub const LIMIT_CONDITION: u16 = 1 << 10;
    /// Bit 11.
    pub const HEARTBEAT: u16 = 1 << 11;
    /// Bit 12.
    pub const ABS_ENC_ERR: u16 = 1 << 12;
    /// Bit 13.
    pub const COMMAND_ACKNOWLEDGE: u16 = 1 << 13;
    /// Bit 14.
    pub const STALL_DETECTED: u16 = 1 << 14;
    /// Bit 15.
    pub const DRIVE_IS_ENABLED: u16 = 1 << 15;
}

/// CMD_word0 command bits (Reference 6, Figure R6.2).
pub mod cmd0 {
    /// Bit 0.
    pub const ABSOLUTE_MOVE: u16 = 1 << 0;
    /// Bit 1.
    pub const RELATIVE_MOVE: u16 = 1 << 1;
    /// Bit 2.
    pub const HOLD_MOVE: u16 = 1 << 2;
    /// Bit 3.
    pub const RESUME_MOVE: u16 = 1 << 3;
    /// Bit 4.
    pub const IMMEDIATE_STOP: u16 = 1 << 4;
    /// Bit 5.
    pub const FIND_HOME_CW: u16 = 1 << 5;
    /// Bit 6.
    pub const FIND_HOME_CCW: u16 = 1 << 6;
    /// Bit 7.
    pub const JOG_CW: u16 = 1 << 7;
    /// Bit 8.
    pub const JOG_CCW: u16 = 1 << 8;
    /// Bit 9.
    pub const PRESET_POSITION: u16 = 1 << 9;
    /// Bit 10.
    pub const RESET_ERRORS: u16 = 1 << 10;
    /// Bit 11.
    pub const PROGRAM_ASSEMBLED: u16 = 1 << 11;
    /// Bit 12.
    pub const READ_ASSEMBLED_DATA: u16 = 1 << 12;
    /// Bit 13.
    pub const RUN_ASSEMBLED_MOVE: u16 = 1 << 13;
    /// Bit 14.
    pub const PRESET_ENCODER: u16 = 1 << 14;
    /// Bit 15.
    pub const MODE_SELECT: u16 = 1 << 15;
}

/// CMD_word1 bits (Reference 6, Figure R6.3).
pub mod cmd1 {
    /// Bit 1: take the move's current from the Motor_Current word.
    pub const MOTOR_CURRENT: u16 = 1 << 1;
    /// Bit 13: Preset Position presets to the scaled encoder position.
    pub const PRESET_TO_ENCODER: u16 = 1 << 13;
    /// Bit 15: Enable_Driver.
    pub const ENABLE_DRIVER: u16 = 1 << 15;
}

/// Target / offset range of Absolute and Relative moves (SMD-R6-034).
pub const POSITION_RANGE: std::ops::RangeInclusive<i32> = -8_388_608..=8_388_607;
/// Highest Velocity (SMD-R6-035).
pub const MAX_VELOCITY: u32 = 2_999_999;
/// Highest Motor_Current word (×0.1 A, SMD-R6-039).
pub const MAX_MOTOR_CURRENT: u16 = 34;
/// The Heartbeat_Bit's half period (SMD-R6-067).
pub const HEARTBEAT_HALF_PERIOD: Duration = Duration::from_millis(500);

/// The 20 output bytes (`0x7000:01–08`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Outputs {
    /// CMD_word0.
    pub cmd0: u16,
    /// CMD_word1.
    pub cmd1: u16,
    /// Position.
    pub position: i32,
    /// Velocity.
    pub velocity: u32,
    /// Acceleration.
    pub acceleration: u16,
    /// Deceleration.
    pub deceleration: u16,
    /// Motor_Current.
    pub motor_current: u16,
    /// Jerk.
    pub jerk: u16,
}

/// The 20 input bytes (`0x6000:01–07`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Inputs {
    /// STATUS_word0.
    pub status0: u16,
    /// STATUS_word1.
    pub status1: u16,
    /// Motor_Position.
    pub motor_position: i32,
    /// Encoder_Position.
    pub encoder_position: i32,
    /// Trapped_Encoder_Position.
    pub trapped_encoder_position: i32,
    /// Motor_Current (×0.1 A) of the last move command.
    pub motor_current: u16,
    /// Jerk of the last move command.
    pub jerk: u16,
}

/// What a running motion segment is for.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Purpose {
    /// An Absolute or Relative move (or its resumption) towards `target`.
    Move,
    /// The controlled stop of a Hold; the move to `target` waits to be resumed.
    HoldStop,
}

/// The curve of a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Curve {
    /// A whole move profile.
    Profile(Profile),
    /// A deceleration from the present speed to the starting speed.
    Ramp(Phase),
}

impl Curve {
    fn duration(&self) -> f64 {
        match self {
            Curve::Profile(p) => p.total_time(),
            Curve::Ramp(r) => r.time,
        }
    }

    fn distance_at(&self, t: f64) -> f64 {
        match self {
            Curve::Profile(p) => p.position_at(t),
            Curve::Ramp(r) => r.distance - r.distance_rising(r.time - t),
        }
    }

    fn speed_at(&self, t: f64) -> f64 {
        match self {
            Curve::Profile(p) => p.speed_at(t),
            Curve::Ramp(r) => r.speed_rising(r.time - t),
        }
    }

    /// (accelerating, decelerating) at `t`.
    fn phase_at(&self, t: f64) -> (bool, bool) {
        match self {
            Curve::Profile(p) => {
                let ta = p.accel.time;
                let tc = ta + p.cruise_time;
                (t < ta, t >= tc && t < p.total_time())
            }
            Curve::Ramp(r) => (false, t < r.time),
        }
    }
}

/// A running segment of motion.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Segment {
    /// Motor position where the segment started (whole steps).
    origin: i64,
    /// +1 clockwise, −1 counter-clockwise.
    dir: i64,
    /// Steps from `origin` already covered when the curve began (a Hold's stop starts mid-move).
    base: f64,
    curve: Curve,
    /// Seconds since the segment started.
    t: f64,
    purpose: Purpose,
    /// Where the move ends (for a Hold: where the resumed move goes).
    target: i64,
    /// The move's parameters (Deceleration and Jerk for a Hold's stop).
    params: Outputs,
}

/// A move brought into its hold state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Held {
    target: i64,
}

/// The unit: configuration, command processing, motion, status.
#[derive(Debug, Clone)]
pub struct Indexer {
    kind: EncoderKind,
    config: Configuration,
    prev: Outputs,
    time: Duration,
    position: i64,
    /// Encoder_Position at the last preset, and the motor steps turned since then: the encoder
    /// turns with the motor, Encoder_Resolution counts per Motor_Resolution steps.
    encoder_base: i64,
    encoder_steps: i64,
    trapped: i32,
    segment: Option<Segment>,
    held: Option<Held>,
    move_complete: bool,
    position_invalid: bool,
    input_error: bool,
    command_error: bool,
    at_home: bool,
    /// The CMD_word0 bit whose success Command_Acknowledge reports, while it stays 1.
    acknowledged: Option<u16>,
    in_current: u16,
    in_jerk: u16,
}

/// The CMD_word0 bits that are commands (all but Mode_Select).
const COMMAND_BITS: u16 = 0x7FFF;

impl Indexer {
    /// A unit at power-up with `config` in memory (Position_Invalid, Stopped, Module_OK).
    pub fn new(kind: EncoderKind, config: Configuration) -> Indexer {
        Indexer {
            kind,
            in_current: config.motor_current,
            config,
            prev: Outputs::default(),
            time: Duration::ZERO,
            position: 0,
            encoder_base: 0,
            encoder_steps: 0,
            trapped: 0,
            segment: None,
            held: None,
            move_complete: false,
            position_invalid: true,
            input_error: false,
            command_error: false,
            at_home: false,
            acknowledged: None,
            in_jerk: 0,
        }
    }

    /// The configuration in memory.
    pub fn config(&self) -> &Configuration {
        &self.config
    }

    /// The encoder kind of the unit.
    pub fn encoder_kind(&self) -> EncoderKind {
        self.kind
    }

    /// Time since power-up.
    pub fn time(&self) -> Duration {
        self.time
    }

    /// True while the configuration in memory breaks a rule of "Invalid Configurations".
    pub fn configuration_error(&self) -> bool {
        !self.config.is_valid(self.kind)
    }

    /// An SDO download to `8010:sub` (1–7) with `value`: stored whatever it is (an invalid value shows
    /// in Configuration_Error), and the position becomes invalid (SMD-R2-012). `false` for another
    /// sub-index.
    pub fn write_config(&mut self, sub: u8, value: u32) -> bool {
        let c = &mut self.config;
        match sub {
            1 => c.cfg0 = value as u16,
            2 => c.cfg1 = value as u16,
            3 => c.starting_speed = value,
            4 => c.motor_resolution = value as u16,
            5 => c.encoder_resolution = value as u16,
            6 => c.idle_current_reduction = value as u16,
            7 => c.motor_current = value as u16,
            _ => return false,
        }
        self.position_invalid = true;
        true
    }

    fn encoder_enabled(&self) -> bool {
        self.config.cfg0 & CFG0_USE_ENCODER != 0
    }

    /// Drive_Is_Enabled: Enable_Driver with a valid configuration (SMD-R5-027, SMD-R6-030).
    fn drive_enabled(&self) -> bool {
        self.prev.cmd1 & cmd1::ENABLE_DRIVER != 0 && !self.configuration_error()
    }

    /// True while a move (or a Hold's stop) is running.
    pub fn is_moving(&self) -> bool {
        self.segment.is_some()
    }

    /// The present speed in steps/s (signed: positive clockwise).
    pub fn speed(&self) -> f64 {
        self.segment
            .map_or(0.0, |s| s.dir as f64 * s.curve.speed_at(s.t))
    }

    /// The motor position without the 32-bit wrap of Motor_Position.
    pub fn position(&self) -> i64 {
        self.position
    }

    /// One process-data exchange: takes `out`, acts on it, runs `dt` of motion, returns the inputs.
    pub fn cycle(&mut self, out: Outputs, dt: Duration) -> Inputs {
        self.take(out);
        self.advance(dt);
        self.inputs()
    }

    /// Acts on new output data (the edges against the previous data).
    fn take(&mut self, out: Outputs) {
        let rising = out.cmd0 & !self.prev.cmd0 & COMMAND_BITS;
        let prev = std::mem::replace(&mut self.prev, out);
        // Command_Acknowledge falls when the host clears the acknowledged bit (SMD-R6-064).
        if let Some(bit) = self.acknowledged {
            if out.cmd0 & bit == 0 {
                self.acknowledged = None;
            }
        }
        if out.cmd0 & cmd0::MODE_SELECT != 0 {
            // Configuration through output data is not modelled: nothing is processed.
            return;
        }
        if rising == 0 {
            let current_edge = out.cmd1 & cmd1::MOTOR_CURRENT & !prev.cmd1;
            if current_edge != 0 {
                // SMD-R6-032 pick: the Motor_Current word applies at once.
                if out.motor_current <= MAX_MOTOR_CURRENT {
                    self.in_current = out.motor_current;
                } else {
                    self.command_error = true;
                }
            }
            return;
        }
        if !rising.is_power_of_two() {
            // Two command bits rising in one update (R6 "Command Bits Must Transition").
            self.command_error = true;
            return;
        }
        // Any command accepted clears At_Home (SMD-R2-022); refused ones set Command_Error.
        let accepted = match rising {
            cmd0::ABSOLUTE_MOVE => self.start_move(out, true),
            cmd0::RELATIVE_MOVE => self.start_move(out, false),
            cmd0::HOLD_MOVE => {
                self.hold();
                true
            }
            cmd0::RESUME_MOVE => self.resume(out),
            cmd0::IMMEDIATE_STOP => {
                self.segment = None;
                self.held = None;
                self.position_invalid = true;
                true
            }
            cmd0::PRESET_POSITION => self.preset_position(out),
            cmd0::RESET_ERRORS => {
                self.command_error = false;
                self.input_error = false;
                self.move_complete = false;
                self.acknowledged = Some(cmd0::RESET_ERRORS);
                true
            }
            cmd0::PRESET_ENCODER => self.preset_encoder(out),
            _ => false,
        };
        if accepted {
            self.at_home = false;
        } else {
            self.command_error = true;
        }
    }

    /// The parameter checks of a move block (SMD-R6-035 … -039).
    fn params_ok(&self, out: &Outputs) -> bool {
        (self.config.starting_speed..=MAX_VELOCITY).contains(&out.velocity)
            && (1..=super::profile::MAX_ACCEL).contains(&out.acceleration)
            && (1..=super::profile::MAX_ACCEL).contains(&out.deceleration)
            && out.jerk <= super::profile::MAX_JERK
            && (out.cmd1 & cmd1::MOTOR_CURRENT == 0 || out.motor_current <= MAX_MOTOR_CURRENT)
    }

    fn start_move(&mut self, out: Outputs, absolute: bool) -> bool {
        if !POSITION_RANGE.contains(&out.position)
            || !self.params_ok(&out)
            || (absolute && self.position_invalid)
            || self.segment.is_some()
            || !self.drive_enabled()
        {
            return false;
        }
        let target = if absolute {
            i64::from(out.position)
        } else {
            self.position + i64::from(out.position)
        };
        // A new move cancels a held one (SMD-R2-033).
        self.held = None;
        self.move_complete = false;
        self.in_current = if out.cmd1 & cmd1::MOTOR_CURRENT != 0 {
            out.motor_current
        } else {
            self.config.motor_current
        };
        self.in_jerk = out.jerk;
        self.run_to(target, out)
    }

    /// Starts the motion to `target` with the parameters of `out`.
    fn run_to(&mut self, target: i64, out: Outputs) -> bool {
        let distance = target - self.position;
        if distance == 0 {
            // SMD-R2-054: accepted, no motion, complete.
            self.move_complete = true;
            return true;
        }
        let Ok(profile) = Profile::plan(MoveParams {
            start_speed: f64::from(self.config.starting_speed),
            speed: f64::from(out.velocity),
            accel: out.acceleration,
            decel: out.deceleration,
            jerk: out.jerk,
            distance: distance.unsigned_abs() as f64,
        }) else {
            return false;
        };
        self.segment = Some(Segment {
            origin: self.position,
            dir: distance.signum(),
            base: 0.0,
            curve: Curve::Profile(profile),
            t: 0.0,
            purpose: Purpose::Move,
            target,
            params: out,
        });
        true
    }

    fn hold(&mut self) {
        let Some(seg) = self.segment else {
            return; // SMD-R2-037: nothing to hold.
        };
        if seg.purpose != Purpose::Move {
            return;
        }
        let v = seg.curve.speed_at(seg.t);
        let vs = f64::from(self.config.starting_speed);
        let ramp = Phase::new(
            vs,
            v.max(vs),
            f64::from(seg.params.deceleration) * 1000.0,
            seg.params.jerk,
        );
        let done = seg.base + seg.curve.distance_at(seg.t);
        let left = (seg.target - seg.origin).unsigned_abs() as f64 - done;
        if ramp.distance >= left {
            return; // Completes on its own deceleration.
        }
        self.segment = Some(Segment {
            base: done,
            curve: Curve::Ramp(ramp),
            t: 0.0,
            purpose: Purpose::HoldStop,
            ..seg
        });
    }

    fn resume(&mut self, out: Outputs) -> bool {
        let Some(held) = self.held else {
            return false; // SMD-R2-035.
        };
        if !self.params_ok(&out) || !self.drive_enabled() {
            return false;
        }
        // The Resume block's parameters, the original target (SMD-R6-044).
        self.held = None;
        self.in_jerk = out.jerk;
        if out.cmd1 & cmd1::MOTOR_CURRENT != 0 {
            self.in_current = out.motor_current;
        }
        self.run_to(held.target, out)
    }

    fn preset_position(&mut self, out: Outputs) -> bool {
        if self.segment.is_some() {
            return false; // SMD-R6-027 pick.
        }
        self.position = if out.cmd1 & cmd1::PRESET_TO_ENCODER != 0 {
            // Motor Position = Encoder Position × steps per turn / counts per turn (SMD-R6-024).
            let enc = i64::from(self.encoder_position());
            let res = i64::from(self.config.encoder_resolution.max(1));
            enc * i64::from(self.config.motor_resolution) / res
        } else {
            i64::from(out.position)
        };
        self.move_complete = false;
        self.position_invalid = false;
        self.acknowledged = Some(cmd0::PRESET_POSITION);
        true
    }

    fn preset_encoder(&mut self, out: Outputs) -> bool {
        if !self.encoder_enabled() {
            return false; // SMD-R6-011 gap pick.
        }
        self.encoder_base = i64::from(out.position);
        self.encoder_steps = 0;
        self.acknowledged = Some(cmd0::PRESET_ENCODER);
        true
    }

    /// Runs the motion for `dt`.
    fn advance(&mut self, dt: Duration) {
        self.time += dt;
        let Some(mut seg) = self.segment else {
            return;
        };
        seg.t += dt.as_secs_f64();
        let before = self.position;
        let end = seg.t >= seg.curve.duration();
        let covered = if end {
            seg.base + seg.curve.distance_at(seg.curve.duration())
        } else {
            seg.base + seg.curve.distance_at(seg.t)
        };
        let total = (seg.target - seg.origin).unsigned_abs() as f64;
        self.position = match (end, seg.purpose) {
            (true, Purpose::Move) => seg.target,
            _ => seg.origin + seg.dir * (covered.min(total).round() as i64),
        };
        if self.encoder_enabled() {
            self.encoder_steps += self.position - before;
        }
        if end {
            self.segment = None;
            match seg.purpose {
                Purpose::Move => self.move_complete = true,
                Purpose::HoldStop => {
                    self.held = Some(Held { target: seg.target });
                }
            }
        } else {
            self.segment = Some(seg);
        }
    }

    fn encoder_position(&self) -> i32 {
        if self.encoder_enabled() {
            let counts = (self.encoder_steps as i128 * i128::from(self.config.encoder_resolution))
                .div_euclid(i128::from(self.config.motor_resolution.max(1)));
            (i128::from(self.encoder_base) + counts) as i64 as i32
        } else {
            0
        }
    }

    /// STATUS_word0 as the unit reports it now.
    pub fn status0(&self) -> u16 {
        let mut s = stat0::MODULE_OK;
        let mut flag = |on: bool, bit: u16| {
            if on {
                s |= bit;
            }
        };
        match self.segment {
            Some(seg) => {
                flag(seg.dir > 0, stat0::MOVING_CW);
                flag(seg.dir < 0, stat0::MOVING_CCW);
                let (acc, dec) = seg.curve.phase_at(seg.t);
                flag(acc, stat0::ACCELERATING);
                flag(dec, stat0::DECELERATING);
            }
            None => flag(true, stat0::STOPPED),
        }
        flag(self.held.is_some(), stat0::IN_HOLD_STATE);
        flag(self.at_home, stat0::AT_HOME);
        flag(self.move_complete, stat0::MOVE_COMPLETE);
        flag(self.position_invalid, stat0::POSITION_INVALID);
        flag(self.input_error, stat0::INPUT_ERROR);
        flag(self.command_error, stat0::COMMAND_ERROR);
        flag(self.configuration_error(), stat0::CONFIGURATION_ERROR);
        s
    }

    /// STATUS_word1 as the unit reports it now.
    pub fn status1(&self) -> u16 {
        let mut s = 0;
        if (self.time.as_millis() / HEARTBEAT_HALF_PERIOD.as_millis()) % 2 == 1 {
            s |= stat1::HEARTBEAT;
        }
        if self.acknowledged.is_some() {
            s |= stat1::COMMAND_ACKNOWLEDGE;
        }
        if self.drive_enabled() {
            s |= stat1::DRIVE_IS_ENABLED;
        }
        s
    }

    /// The 20 input bytes as the unit reports them now.
    pub fn inputs(&self) -> Inputs {
        Inputs {
            status0: self.status0(),
            status1: self.status1(),
            motor_position: self.position as i32,
            encoder_position: self.encoder_position(),
            trapped_encoder_position: self.trapped,
            motor_current: self.in_current,
            jerk: self.in_jerk,
        }
    }
}
