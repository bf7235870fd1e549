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
//! counting with the motor; the two DC inputs (function and active level from the configuration,
//! IN1_Active/IN2_Active), E-Stop, the end limits during moves and at their start, Limit_Condition,
//! Input_Error, the captures into Trapped_Encoder_Position; Jog moves (speed, acceleration and
//! deceleration changed while running, Invalid_Jog_Change, the Stop Jog input, hold and resume).
//! Find Home CW/CCW with the three profiles of Reference 4 (Home input only, Backplane_Proximity_Bit,
//! overtravel limit), the 2 s pauses, the home input or limit already active at the start.
//! Registration moves (Stopping Distance run-out, Minimum Registration Move Distance, level-triggered
//! stop conditions, the abrupt stop of a short run-out).
//! Stall detection (45° between motor and encoder, against a reference taken at power-up, on
//! configuration writes, presets, homing and Reset Errors; a blocked or externally turned shaft);
//! driver faults (over-temperature at 95 °C with Temperature_Above_90°C, STO inputs, an internal fault
//! for Module_OK); the motor current as the driver supplies it, with idle current reduction.
//! Assembled moves: the programming handshake (In_Assembled_Mode, Waiting_For_Assembled_Segment,
//! up to 16 segments, Save_to_Flash), Blend and Dwell runs; indexed moves (CMD_word1 bit 8) started
//! by the Start Indexed input, re-triggered while the command stays, cancelled when it is cleared.
//! The EtherCAT state as the unit sees it (PreOp_SafeOp, commands only in Op, the position invalid
//! after leaving Op, the SyncManager watchdog), Mode_Select (Mode_Flag, no commands, no heartbeat),
//! the absolute encoder (its count kept through a power cycle, the offset of Preset Encoder kept only
//! when saved to flash, Abs_Enc_Err kept until a power cycle) against the incremental one (zero at
//! every power-up).
//! DC_Sync (CFG_Word_1 bit 6): a move waits for the next SYNC0 event and starts 520 µs after it.
//!
//! Choices where the manual is silent (catalogue picks unless said otherwise):
//! - Hold during the final deceleration of a move whose controlled stop would pass the target: the move
//!   simply completes (Move_Complete), there is nothing left to hold.
//! - A Hold's controlled stop decelerates from the present speed at the move's Deceleration and Jerk.
//! - A rejected command leaves Move_Complete as it was (SMD-R6-040 speaks of a move not yet complete).
//! - Preset Position with CMD_word1 bit 13 and the encoder disabled presets to 0 (Encoder_Position reads 0).
//! - E-Stop and an end limit that stop the motor also cancel a held move (as Immediate Stop does,
//!   SMD-R6-028).
//! - A jog's speed changes use the Jerk word in force at that moment.
//! - Homing: a limit in the requested direction met while turning that way (search or return) is the
//!   overtravel profile; met while backing off it is ignored. Hold aborts a homing run with a controlled
//!   stop (SMD-R2-036): no hold state, no Move_Complete, positions not zeroed. A homing run in a 2 s
//!   pause counts as a move in progress (no other move, no preset), and Stopped reads 1 in the pause.
//! - Find Home without an input configured as Home is a Command_Error (SMD-R4-004 gap).
//! - Registration: linear acceleration, 8010:07 as the current, in.Jerk 0 (SMD-R6-043, SMD-R2-023
//!   gaps); Velocity/Acceleration/Deceleration may change while it runs, as for a jog; a run-out
//!   longer than the braking distance cruises at the present speed, then brakes to V_S exactly at the
//!   end (SMD-R2-065 gap).
//! - Over-temperature: the fault clears itself at or below 90 °C (hysteresis of the model,
//!   SMD-R6-071 gap). A driver fault (over-temperature or STO) during motion ends it like an
//!   Immediate Stop (SMD-R1-004 gap); while a driver fault is present, moves are refused with
//!   Command_Error. Drive_Is_Enabled stays 1 through an over-temperature fault and only an STO
//!   fault (besides Enable_Driver 0 or a configuration error) clears it (SMD-R6-062 pick, against
//!   CMD_word1 bit 15's "an Overtemperature Fault … will prevent the motor enable").
//! - Abs_Enc_Err: once set it stays until power is cycled, whatever its cause does meanwhile; at
//!   power-up it is set again while a battery or encoder fault is still present (SMD-R6-066).
//! - Idle current: the motor current drops to `8010:06` % of the last move's current 1.5 s after the
//!   motor stops (any stop) and returns as soon as it moves; a new percentage applies from the end of
//!   the first move after it was written (SMD-R5-008).
//! - Assembled moves: Program_Assembled while a move runs is a Command_Error; other CMD_word0 commands
//!   during programming are Command_Errors; the segment's Motor_Current word is ignored; a Blend runs
//!   its speed changes with each segment's Jerk; at the last segment it brakes with the last segment's
//!   Deceleration (linear) so as to reach V_S exactly at the end. in.Jerk reports the first segment's.
//! - Indexed commands are checked when they are triggered, not when they are latched.
//! - The model starts in Op (as after the master's start-up); [`Indexer::set_network_state`] moves it.
//!   Leaving Op stops a move at once and makes the position invalid (SMD-R6-056 gap); the first
//!   output data after entering Op is its own edge reference: a bit already 1 in it is no edge
//!   (SMD-R6-073 gap). [`Indexer::exchange_held`] is an exchange without new output data (none came
//!   from the master), which takes no edge and no reference.
//!
//! # Methods and polling order
//!
//! On the host's clock: [`Indexer::start`] at power-on with the exchange period, then one
//! [`Indexer::exchange`] per process-data exchange with its time, when [`Indexer::poll_timeout`] has
//! come; the model runs the motion since the previous exchange (it derives the time step itself).
//! The EtherCAT state ([`Indexer::set_network_state`]), the SyncManager watchdog
//! ([`Indexer::sm_watchdog_expired`]), SYNC0 events ([`Indexer::sync0_event`]) and the harness
//! (inputs, shaft, temperature, configuration) come between exchanges, each with its instant as its
//! first argument: the SYNC0 event and the watchdog act at their instant, the wiring and the driver's
//! conditions are sensed at the next exchange (as the unit samples them), the rest acts at once.
//! [`Indexer::cycle`] is the same exchange with the time step given, for runs without a clock: its
//! instant is worked out from [`Indexer::start`] and the time steps ([`Indexer::last_exchange`]).

use std::time::{Duration, Instant};

use super::config::{Cfg0, Configuration, EncoderKind, InputFunction, CFG0_USE_ENCODER};
use super::profile::{MoveParams, Phase, Profile};

mod assembled;
mod commands;
mod dc_inputs;
mod drive;
mod encoder;
mod homing;
mod jog;
mod motion;
mod network;
mod registration;
mod words;

use assembled::AssembledRun;
pub use assembled::{AssembledSegment, MAX_SEGMENTS};
use commands::Outcome;
pub use commands::{MAX_MOTOR_CURRENT, MAX_VELOCITY, POSITION_RANGE};
pub use drive::{IDLE_DELAY, OVER_TEMPERATURE, OVER_TEMPERATURE_CLEAR, TEMPERATURE_WARNING};
pub use encoder::ABS_ENCODER_MAX_ACCEL;
use homing::Homing;
pub use homing::HOMING_PAUSE;
use jog::Jog;
use motion::{limit_towards, Curve, Held, Purpose, Segment};
pub use network::{NetworkState, SYNC0_START_DELAY};
pub use words::{cmd0, cmd1, stat0, stat1, Inputs, Outputs, HEARTBEAT_HALF_PERIOD};

/// Where a new move stands with DC_Sync on (SMD-R1-022).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SyncWait {
    /// The next SYNC0 event is still to come.
    ForSync0,
    /// SYNC0 came: the motion starts once this much more time has passed.
    Delay(Duration),
}

/// The unit: configuration, command processing, inputs, motion, status.
#[derive(Debug, Clone)]
pub struct Indexer {
    kind: EncoderKind,
    config: Configuration,
    /// `config` breaks a rule of "Invalid Configurations" (kept with it: it changes only with it).
    config_error: bool,
    /// The configuration at power-up (online CoE writes are lost at power-off, SMD-T2-006).
    power_up_config: Configuration,
    prev: Outputs,
    time: Duration,
    /// The instant of the last exchange (or of [`Indexer::start`]); a clockless
    /// [`Indexer::cycle`] moves it on by its time step.
    last_exchange: Option<Instant>,
    /// The instant the motion has run to: the last exchange's, or that of a later event that
    /// stopped it ([`Indexer::sm_watchdog_expired`]). The next exchange runs the motion from here.
    ran_to: Option<Instant>,
    /// The process-data exchange period the unit runs at (from [`Indexer::start`]).
    period: Option<Duration>,
    position: i64,
    /// Encoder_Position at the last preset, and the motor steps turned since then: the encoder
    /// turns with the motor, Encoder_Resolution counts per Motor_Resolution steps.
    encoder_base: i64,
    encoder_steps: i64,
    /// Counts the shaft was turned by an outside force (added to the encoder).
    encoder_extra: i64,
    /// The shaft cannot turn (a hard stop, a missing motor supply): the encoder stands still.
    shaft_blocked: bool,
    /// The stall comparison's reference: (motor position, encoder position).
    stall_ref: (i64, i64),
    stall: bool,
    /// Internal temperature, °C.
    temperature: f64,
    over_temperature: bool,
    /// Whether each STO input is powered.
    sto_powered: [bool; 2],
    sto_fault: bool,
    internal_fault: bool,
    /// When the motor last stopped (for the idle current reduction).
    stopped_since: Duration,
    /// The idle percentage in force (a new 8010:06 applies after the next move).
    idle_pct: u16,
    trapped: i32,
    /// Whether current flows into IN1 / IN2.
    current: [bool; 2],
    /// IN1 / IN2 active at the last cycle.
    was_active: [bool; 2],
    segment: Option<Segment>,
    held: Option<Held>,
    homing: Option<Homing>,
    /// The stored assembled move (RAM), the one saved to flash, the one being programmed.
    program: Option<Vec<AssembledSegment>>,
    flash_program: Option<Vec<AssembledSegment>>,
    programming: Option<Vec<AssembledSegment>>,
    waiting_for_segment: bool,
    /// After a save to flash every command is ignored until power is cycled (SMD-R2-089 gap).
    flash_lockout: bool,
    assembled: Option<AssembledRun>,
    /// An indexed command waiting for the Start Indexed input: its bit and its data.
    pending_index: Option<(u16, Outputs)>,
    /// The last cycle's length, seconds (a Blend looks one cycle ahead to brake in time).
    last_dt: f64,
    network: NetworkState,
    /// Op was entered and no output data has come since: the first that comes is the edge
    /// reference (SMD-R6-073).
    edge_reference_pending: bool,
    /// DC_Sync: the new move waits for SYNC0, then for its start delay.
    sync_wait: Option<SyncWait>,
    /// CMD_word0 bit 15 (Mode_Select) is 1: configuration mode, nothing processed.
    mode_flag: bool,
    /// Time in Command Mode, which the heartbeat follows.
    heartbeat_time: Duration,
    /// The encoder offset saved to flash (absolute units, SMD-R6-012).
    flash_encoder_offset: i64,
    /// Abs_Enc_Err (STATUS_word1 bit 12): set by its condition, kept until power is cycled
    /// (SMD-R6-066).
    abs_encoder_error: bool,
    /// A battery or encoder fault of the absolute encoder is present (it stays through a power
    /// cycle).
    abs_encoder_fault: bool,
    move_complete: bool,
    position_invalid: bool,
    input_error: bool,
    command_error: bool,
    at_home: bool,
    /// The input (0 or 1) whose end limit stopped a move, until it goes inactive (Limit_Condition).
    limit_condition: Option<usize>,
    invalid_jog_change: bool,
    /// The CMD_word0 bit whose success Command_Acknowledge reports, while it stays 1.
    acknowledged: Option<u16>,
    in_current: u16,
    in_jerk: u16,
}

impl Indexer {
    /// A unit at power-up with `config` in memory (Position_Invalid, Stopped, Module_OK).
    pub fn new(kind: EncoderKind, config: Configuration) -> Indexer {
        Indexer {
            kind,
            in_current: config.motor_current,
            config,
            config_error: !config.is_valid(kind),
            power_up_config: config,
            prev: Outputs::default(),
            time: Duration::ZERO,
            last_exchange: None,
            ran_to: None,
            period: None,
            position: 0,
            encoder_base: 0,
            encoder_steps: 0,
            encoder_extra: 0,
            shaft_blocked: false,
            stall_ref: (0, 0),
            stall: false,
            temperature: 40.0,
            over_temperature: false,
            sto_powered: [true; 2],
            sto_fault: false,
            internal_fault: false,
            stopped_since: Duration::ZERO,
            idle_pct: config.idle_current_reduction,
            trapped: 0,
            current: [false; 2],
            was_active: [false; 2],
            segment: None,
            held: None,
            homing: None,
            program: None,
            flash_program: None,
            programming: None,
            waiting_for_segment: false,
            flash_lockout: false,
            assembled: None,
            pending_index: None,
            last_dt: 0.001,
            network: NetworkState::Op,
            edge_reference_pending: false,
            sync_wait: None,
            mode_flag: false,
            heartbeat_time: Duration::ZERO,
            flash_encoder_offset: 0,
            abs_encoder_error: false,
            abs_encoder_fault: false,
            move_complete: false,
            position_invalid: true,
            input_error: false,
            command_error: false,
            at_home: false,
            limit_condition: None,
            invalid_jog_change: false,
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
        self.config_error
    }

    /// An SDO download at `now` to `8010:sub` (1–7) with `value`, acted on at once: stored whatever it is (an invalid value shows
    /// in Configuration_Error), and the position becomes invalid (SMD-R2-012). `false` for another
    /// sub-index.
    pub fn write_config(&mut self, _now: Instant, sub: u8, value: u32) -> bool {
        if !self.config.set(sub, value) {
            return false;
        }
        self.config_error = !self.config.is_valid(self.kind);
        self.position_invalid = true;
        self.stall_reference();
        // A configuration write clears a RAM-only assembled move; a flash copy is active again
        // (SMD-R2-081, SMD-R2-082 pick).
        self.program = self.flash_program.clone();
        true
    }

    /// True while the motor turns (a move, a jog or a controlled stop).
    pub fn is_moving(&self) -> bool {
        self.segment.is_some()
    }

    /// The present speed in steps/s (signed: positive clockwise).
    pub fn speed(&self) -> f64 {
        self.segment.map_or(0.0, |s| s.dir as f64 * s.speed())
    }

    /// The motor position without the 32-bit wrap of Motor_Position.
    pub fn position(&self) -> i64 {
        self.position
    }

    /// Starts the model's clock at `now` (power-on), exchanging process data every `period`: the
    /// first [`Indexer::exchange`] runs the motion since then, and [`Indexer::poll_timeout`] tells
    /// when the next exchange is due.
    pub fn start(&mut self, now: Instant, period: Duration) {
        self.last_exchange = Some(now);
        self.ran_to = Some(now);
        self.period = Some(period);
    }

    /// When the next process-data exchange is due: the last exchange (or [`Indexer::start`]) plus
    /// the period; `None` before [`Indexer::start`].
    pub fn poll_timeout(&self) -> Option<Instant> {
        self.last_exchange.zip(self.period).map(|(t, p)| t + p)
    }

    /// The instant of the last exchange (or of [`Indexer::start`]): on the host's clock, or worked
    /// out by [`Indexer::cycle`] from the start and its time steps; `None` before the first of them.
    pub fn last_exchange(&self) -> Option<Instant> {
        self.last_exchange
    }

    /// One process-data exchange at `now`: takes `out`, acts on the inputs and on the commands, runs
    /// the motion since the previous exchange (none before the first, without [`Indexer::start`]),
    /// returns the inputs.
    pub fn exchange(&mut self, now: Instant, out: Outputs) -> Inputs {
        let dt = self.since_last_exchange(now);
        self.run(Some(out), dt)
    }

    /// One process-data exchange at `now` without new output data (the master's did not come): the
    /// last output data stays in force, no edge is taken from it, and after entering Op the first
    /// output data still to come is the edge reference (SMD-R6-073).
    pub fn exchange_held(&mut self, now: Instant) -> Inputs {
        let dt = self.since_last_exchange(now);
        self.run(None, dt)
    }

    /// The time the motion has to run to reach `now` (none before the first exchange, without
    /// [`Indexer::start`]); `now` is the last exchange.
    fn since_last_exchange(&mut self, now: Instant) -> Duration {
        let dt = self
            .ran_to
            .map_or(Duration::ZERO, |t| now.saturating_duration_since(t));
        self.last_exchange = Some(self.last_exchange.map_or(now, |t| t.max(now)));
        self.ran_to = Some(self.ran_to.map_or(now, |t| t.max(now)));
        dt
    }

    /// One process-data exchange without a clock: takes `out`, acts on the inputs and on the
    /// commands, runs `dt` of motion, returns the inputs. The exchange's instant is worked out, not
    /// read: the last exchange's plus `dt` (after [`Indexer::start`]; see
    /// [`Indexer::last_exchange`]).
    pub fn cycle(&mut self, out: Outputs, dt: Duration) -> Inputs {
        let dt = self.step_instant(dt);
        self.run(Some(out), dt)
    }

    /// [`Indexer::cycle`] without new output data (see [`Indexer::exchange_held`]).
    pub fn cycle_held(&mut self, dt: Duration) -> Inputs {
        let dt = self.step_instant(dt);
        self.run(None, dt)
    }

    /// A clockless exchange of `dt`: the instant of the last exchange moves on by `dt` (after
    /// [`Indexer::start`]); the time the motion runs (`dt` less what an event ran of it already).
    fn step_instant(&mut self, dt: Duration) -> Duration {
        match self.last_exchange {
            Some(t) => self.since_last_exchange(t + dt),
            None => dt,
        }
    }

    /// Runs the motion from where it stands up to `now`, between exchanges (no output data, no
    /// input edges): an event at `now` then finds the motor where it is at `now`. Nothing before
    /// the first exchange or [`Indexer::start`], nor for an instant the motion has reached.
    pub(super) fn run_motion_to(&mut self, now: Instant) {
        let Some(from) = self.ran_to.filter(|&t| t < now) else {
            return;
        };
        self.ran_to = Some(now);
        let was_moving = self.segment.is_some();
        self.advance(now - from);
        self.after_motion(was_moving);
    }

    /// One exchange of `dt`, with new output data `out` or none.
    fn run(&mut self, out: Option<Outputs>, dt: Duration) -> Inputs {
        let was_moving = self.segment.is_some();
        self.check_driver();
        self.sense_inputs();
        if let Some(out) = out {
            self.take(out);
        }
        // A jog follows the output data in force: the new, or the last.
        self.follow_jog(self.prev);
        self.advance(dt);
        self.after_motion(was_moving);
        self.inputs()
    }

    /// What follows a run of the motion: the end of a move, the stall check.
    fn after_motion(&mut self, was_moving: bool) {
        if was_moving && self.segment.is_none() {
            self.stopped_since = self.time;
            // A new idle percentage applies from the end of a move (SMD-R5-008).
            self.idle_pct = self.config.idle_current_reduction;
        }
        self.check_stall();
    }

    /// The unit after its power was cycled: the power-up state with the power-up configuration (online
    /// writes are lost, SMD-T2-006) and the flash contents (an assembled move saved to flash,
    /// SMD-R2-082).
    pub fn power_cycle(&mut self) {
        self.power_cycle_turned(0, 0.0);
    }

    /// A power cycle during which the unpowered shaft was turned by `counts` encoder counts with a
    /// peak acceleration of `peak_accel` °/s². An absolute encoder keeps its count, the turning
    /// included, unless the acceleration exceeded 160,000 °/s² (Abs_Enc_Err, SMD-R1-016,
    /// SMD-R1-017); its offset is the one saved to flash (SMD-R6-012, SMD-R6-013). An incremental
    /// encoder starts at 0 (SMD-R1-014).
    pub fn power_cycle_turned(&mut self, counts: i64, peak_accel: f64) {
        let old = std::mem::replace(self, Indexer::new(self.kind, self.power_up_config));
        // The host's clock goes on, and so do the exchanges.
        self.last_exchange = old.last_exchange;
        self.ran_to = old.ran_to;
        self.period = old.period;
        self.flash_program = old.flash_program.clone();
        self.program = old.flash_program;
        self.flash_encoder_offset = old.flash_encoder_offset;
        if self.kind == EncoderKind::Absolute {
            self.encoder_steps = old.encoder_steps;
            self.encoder_extra = old.encoder_extra + counts;
            self.encoder_base = old.flash_encoder_offset;
            // SMD-R6-066: Abs_Enc_Err is evaluated again at power-up: set by the over-acceleration
            // (SMD-R1-017) or by a battery or encoder fault still present, clear otherwise.
            self.abs_encoder_fault = old.abs_encoder_fault;
            self.abs_encoder_error = peak_accel > ABS_ENCODER_MAX_ACCEL || old.abs_encoder_fault;
        }
        self.stall_reference();
    }
}
