//! A generic, sans-IO CiA 402 drive: one axis of any vendor's drive description with the CiA 402
//! objects, made a live device (CiA 402-2: device control, profile position, profile velocity,
//! homing, cyclic synchronous position/velocity/torque modes).
//!
//! A CANopen node (or an EtherCAT CoE slave) hosts one [`Drive`] per axis as its application:
//!
//! - **Objects.** The node routes SDO/PDO reads and writes of the objects the drive owns through
//!   [`od::hook::DeviceHook`] ([`Drive::owns`](od::hook::DeviceHook::owns), `read`, `check`,
//!   `write`). Process values (0x6041, 0x6064, …) are read from the drive; parameters and targets
//!   stay in the dictionary, the drive keeps its own copy of what is written.
//! - **Time.** Nothing inside reads a clock. The drive runs its control loop in ticks of
//!   [`DriveConfig::tick`] on a grid from the instant it was made (or reset); every input carries
//!   `now` and first runs the ticks up to it. Call [`Drive::sync`] on every SYNC (CANopen, after
//!   applying synchronous RPDOs and before sampling synchronous TPDOs) or SYNC0 (EtherCAT DC), and
//!   [`Drive::handle_timeout`] when [`Drive::poll_timeout`] says. `poll_timeout` answers the next
//!   tick while anything moves or may change, and `None` while the drive stands idle with its power
//!   stage off.
//! - **Writes** through the hook carry no time: they take effect at the drive's clock, the last tick
//!   up to the latest `now` it was given. A node calls `handle_timeout(now)` with the time of the
//!   frame before delivering its writes, and then exact timing follows. An idle drive's clock
//!   stands still; when a write reached it idle and the next `handle_timeout`/`sync` comes more
//!   than one tick after its clock, the node evidently did not keep the clock current, and the
//!   write is taken as made at that `now` (the motion it started begins there, not in the past).
//! - **Reads** answer the state at the last tick processed.
//!
//! The runtime loop of a node: receive a frame → deliver writes through the hook (and `sync` on a
//! SYNC) → send what is due (TPDOs read through the hook) → sleep until the earliest of its own
//! timers and [`Drive::poll_timeout`] → [`Drive::handle_timeout`].
//!
//! ```
//! use std::time::{Duration, Instant};
//! use ds402::drive::{Drive, DriveConfig};
//! use od::hook::Bound;
//! use od::sdo::store::ObjectStore;
//! use od::{AccessType, Address, DataType, Dictionary, Object, SubObject};
//!
//! let mut dict = Dictionary::new();
//! for (index, name, ty, access) in [
//!     (0x6040, "Controlword", DataType::Unsigned16, AccessType::Rww),
//!     (0x6041, "Statusword", DataType::Unsigned16, AccessType::Ro),
//!     (0x6060, "Modes of operation", DataType::Integer8, AccessType::Rww),
//!     (0x6061, "Modes of operation display", DataType::Integer8, AccessType::Ro),
//!     (0x6064, "Position actual value", DataType::Integer32, AccessType::Ro),
//!     (0x607A, "Target position", DataType::Integer32, AccessType::Rww),
//!     (0x6081, "Profile velocity", DataType::Unsigned32, AccessType::Rw),
//! ] {
//!     dict.insert(Object::var(index, SubObject::new(name, ty, access)));
//! }
//! assert_eq!(Drive::axes(&dict), vec![0]);
//! let t0 = Instant::now();
//! let mut drive = Drive::from_dictionary(&dict, 0, DriveConfig::default(), t0).unwrap();
//! drive.handle_timeout(t0 + Duration::from_millis(1)); // Switch on disabled
//! let mut node = Bound::new(&mut dict, &mut drive, t0 + Duration::from_millis(1));
//! node.download(Address::new(0x6060, 0), &[1]).unwrap(); // profile position
//! for cw in [0x06u16, 0x07, 0x0F] {
//!     node.download(Address::new(0x6040, 0), &cw.to_le_bytes()).unwrap();
//! }
//! // Operation enabled, standing (target reached), remote.
//! assert_eq!(node.upload(Address::new(0x6041, 0)), Ok(vec![0x37, 0x06]));
//! ```
//!
//! The parts, each an `impl Drive` block or a helper of its own file:
//! - `state`: the state machine with its option codes, faults and the status word's state bits;
//! - `modes`: the modes of operation (pp, pv, csp, csv, cst), halt, target reached, following
//!   error, software limits;
//! - `limits`: the demand of csp and csv within the drive's limits, and the line the drive logs
//!   when a limit holds it back ([`Limited`], [`Drive::poll_limit`]);
//! - `homing`: homing mode, methods 1–14, 17–30, 33, 34, 35 and 37;
//! - `motor`: the servo and stepper models; `profile`: the trapezoidal profiles;
//! - `switches`: the simulated limit and home switches and index pulses;
//! - `objects`: the owned objects, the parameters' rules and the [`od::hook::DeviceHook`];
//! - `factory`: what a drive reports where its description gives no value, and the factory
//!   settings it takes where the description's value would stop it ([`fill`], which a node calls
//!   on the dictionary before it makes its drives).
//!
//! # Picks where CiA 402 leaves room
//!
//! - Units: positions in encoder counts, velocities in counts/s, accelerations in counts/s² (the
//!   factor group is not applied); 0x6080 max motor speed in rpm. 0x6063 reads as 0x6064, 0x60FC as
//!   0x6062.
//! - Status word: bit 4 (voltage enabled) in Switched on, Operation enabled, Quick stop active and
//!   a braking Fault reaction active; bit 5 is 1 except in Quick stop active; bit 9 always 1; bit 7
//!   (warning) while the following error is beyond its window before its time-out; bit 11 while the
//!   target in processing was clamped by the software limits (0x607D, on when min < max) or a limit
//!   switch is active; bits 10/12/13 only in Operation enabled and Quick stop active (there bit 10
//!   is "standing still").
//! - pp: target reached when the profile has ended at the target and, with a position window
//!   (0x6067 ≠ 0xFFFFFFFF), the actual position has been within it for 0x6068 ms; a set-point with
//!   bit 5 = 0 during a move is buffered (one deep; set-point acknowledge stays 1 while it waits);
//!   relative moves follow 0x60F2 bits 0–1; 0x6086 takes 0 only (other values are refused with
//!   0x06090030).
//! - pv: target reached when |0x606C − target| ≤ 0x606D has held for 0x606E ms; bit 12 (speed = 0)
//!   is 0 once |0x606C| > 0x606F has held for 0x6070 ms.
//! - Following error (0x6065 window, 0x6066 time-out; monitored in pp and csp): beyond the window
//!   the warning bit 7 is set; beyond it for 0x6066 ms, bit 13 (following error) instead. In pp the
//!   move goes on (the master decides); in csp the drive faults with 0x8611 at that instant, and bit
//!   13 stays set in Fault reaction active and Fault until Fault reset. 0x6065
//!   = 0xFFFFFFFF switches the monitor off, and so does 0 (an EDS entry without a default value).
//! - Running into an active limit switch outside homing faults with 0x8612 (reference limit).
//! - Cyclic modes: the target of each SYNC is reached one interpolation period later (the network's
//!   SYNC cycle where it gives one, [`Drive::set_sync_cycle`]; else 0x60C2 when present, else the
//!   time between the last two SYNCs); bit 12 is 1 while following; bit 10 is 1
//!   only when standing after a halt. A step of the set-points beyond the drive's limits (0x607F,
//!   0x6080, 0x60C5, 0x60C6, and the acceleration the motor's torque gives) is not followed: the
//!   demand runs after the set-points within them and lands on them exactly, and the drive logs
//!   which limit held it back (see `limits`), as it does for a clamped target and for the faults
//!   it raises.
//! - Stepper: 0x6064 counts the rotor (an encoder is assumed, [`MotorConfig::encoder`]); without
//!   encoder it counts commanded steps.
//! - Power off: the rotor coasts on viscous friction; the load torque does not move it.
//! - Disable operation and Shutdown with option code 1 brake in Operation enabled and change state
//!   at standstill; "current limit" and "voltage limit" (0x605A, 0x605D, 0x605E) both brake at the
//!   deceleration the torque limit 0x6072 allows.
//! - Modes: 0x6060 takes the modes 0x6502 declares that this drive implements (vl, tq and ip are
//!   refused even when declared); without 0x6502 (or with 0x6502 = 0, an entry without a value),
//!   the modes whose objects the dictionary has (a cyclic mode needs 0x60C2 as well, unless the
//!   network's SYNC has a clock of its own, [`DriveConfig::sync_clock`]). A mode change takes effect at once (0x6061
//!   follows); a set-point or homing start is taken only in Operation enabled.
//! - Parameters: an acceleration, deceleration or homing speed of 0 in the dictionary (an EDS entry
//!   without a default) is taken as this drive's default; a write of 0 is refused (0x06090032).
//!   [`fill`] gives such entries (and every other value the drive's rules would refuse written
//!   back) the value the drive runs with, so that what the drive reports, it takes back.
//!   0x608F is written only with the power stage off (0x08000022).
//! - Faults: the drive raises 0x8611 and 0x8612 itself, [`Drive::raise_fault`] injects others;
//!   their causes latch, so Fault reset always leaves Fault.

use std::time::{Duration, Instant};

use od::dict::Dictionary;

use crate::cia402::State;

mod factory;
mod homing;
mod limits;
mod modes;
mod motor;
mod objects;
mod profile;
mod state;
mod switches;

pub use factory::{device_type, fill, PROFILE_402, SEVERAL_DEVICES, TYPE_SERVO, TYPE_STEPPER};
pub use homing::HomingStatus;
pub use limits::Limited;
pub use objects::IMPLEMENTED_MODES;
pub use state::{
    ERROR_FOLLOWING, ERROR_REFERENCE_LIMIT, SW_INTERNAL_LIMIT, SW_OMS12, SW_OMS13, SW_QUICK_STOP,
    SW_REMOTE, SW_TARGET_REACHED, SW_VOLTAGE_ENABLED, SW_WARNING,
};
pub use switches::{HOME_SWITCH, NEGATIVE_LIMIT, POSITIVE_LIMIT};

/// The kind of motor behind the drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MotorKind {
    /// A servo motor with encoder, position/velocity controlled.
    Servo,
    /// A stepper motor: open loop, loses steps beyond its pull-out torque.
    Stepper,
}

/// The simulated motor and load.
#[derive(Clone, Debug, PartialEq)]
pub struct MotorConfig {
    /// Servo or stepper.
    pub kind: MotorKind,
    /// Encoder counts per revolution, 10 000 by default; 0x608F:01 / 0x608F:02 when the dictionary
    /// has them (non-zero).
    pub counts_per_rev: u32,
    /// Rotor inertia, kg·m² (default 1e-4).
    pub rotor_inertia: f64,
    /// Load inertia on the shaft, kg·m² (default 0).
    pub load_inertia: f64,
    /// Rated torque, N·m (default 1.0); 0x6076 (mN·m) when the dictionary has it (non-zero).
    pub rated_torque: f64,
    /// Peak torque, per mille of the rated torque (default 3000); 0x6072 when the dictionary has it
    /// (non-zero).
    pub peak_torque_permille: u16,
    /// Stepper only: the torque beyond which the rotor slips, N·m (default 0.5).
    pub pull_out_torque: f64,
    /// A constant external torque pulling towards negative positions, N·m (default 0).
    pub load_torque: f64,
    /// Viscous friction, N·m·s/rad (default 1e-3).
    pub friction: f64,
    /// Stepper only: full steps per revolution (default 200).
    pub full_steps_per_rev: u32,
    /// Stepper only: whether an encoder reads the rotor (default true). With it 0x6064 counts the
    /// rotor and shows lost steps; without it 0x6064 counts commanded steps.
    pub encoder: bool,
}

impl Default for MotorConfig {
    fn default() -> Self {
        MotorConfig {
            kind: MotorKind::Servo,
            counts_per_rev: 10_000,
            rotor_inertia: 1e-4,
            load_inertia: 0.0,
            rated_torque: 1.0,
            peak_torque_permille: 3000,
            pull_out_torque: 0.5,
            load_torque: 0.0,
            friction: 1e-3,
            full_steps_per_rev: 200,
            encoder: true,
        }
    }
}

/// The simulated machine: switches and the index pulse, in raw rotor counts (0x6064 before any
/// homing).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SimConfig {
    /// The negative limit switch (0x60FD bit 0) is active at and below this position.
    pub negative_limit: Option<i64>,
    /// The positive limit switch (0x60FD bit 1) is active at and above this position.
    pub positive_limit: Option<i64>,
    /// The home switch (0x60FD bit 2) is active at and above this position…
    pub home_switch: Option<i64>,
    /// …and below this one, when set (a cam, as homing methods 7–14 and 23–30 expect).
    pub home_switch_end: Option<i64>,
    /// An index pulse each `counts_per_rev` counts at this offset.
    pub index_offset: i64,
}

/// How a [`Drive`] runs.
#[derive(Clone, Debug, PartialEq)]
pub struct DriveConfig {
    /// The control period (default 1 ms; at least 1 µs).
    pub tick: Duration,
    /// The motor.
    pub motor: MotorConfig,
    /// The machine around it.
    pub sim: SimConfig,
    /// The network's SYNC runs on a clock of its own (EtherCAT's SYNC0; not CANopen's SYNC
    /// messages): the cyclic synchronous modes need no interpolation period 0x60C2 to run, so a
    /// dictionary without 0x6502 supports them where it has their target (0x607A csp, 0x60FF csv,
    /// 0x6071 cst). Default false.
    pub sync_clock: bool,
}

impl Default for DriveConfig {
    fn default() -> Self {
        DriveConfig {
            tick: Duration::from_millis(1),
            motor: MotorConfig::default(),
            sim: SimConfig::default(),
            sync_clock: false,
        }
    }
}

/// The position and velocity demand, raw counts and counts/s.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Demand {
    p: f64,
    v: f64,
}

/// Where the demand comes from at each tick.
#[derive(Clone, Debug, PartialEq)]
enum Motion {
    /// Power off: the demand follows the rotor.
    Free,
    /// Standing at the demand position.
    Hold,
    /// A planned profile, evaluated from tick `origin`.
    Plan {
        profile: profile::Profile,
        origin: u64,
    },
    /// Cyclic synchronous position: from `from` at `at` to `to` one `period` later.
    Position {
        from: f64,
        to: f64,
        at: Instant,
        period: Duration,
    },
    /// Cyclic synchronous velocity: from `from` at `at` to `to` one `period` later.
    Velocity {
        from: f64,
        to: f64,
        at: Instant,
        period: Duration,
    },
    /// Cyclic synchronous torque, per mille of the rated torque.
    Torque { permille: f64 },
}

/// One axis of a CiA 402 drive. See the [module documentation](self).
#[derive(Clone, Debug)]
pub struct Drive {
    axis: u8,
    config: DriveConfig,
    tick_ns: u64,
    grid: Instant,
    ticks: u64,
    /// An input reached the drive while it stood idle: it asks for its next tick, so that whoever
    /// runs it (the node checking its event-driven TPDOs at the application's ticks) sees what the
    /// input changed.
    touched: bool,
    params: objects::Params,
    power_on: objects::Params,
    process_types: Vec<(u16, od::types::DataType)>,
    supported: u32,
    state: State,
    control: u16,
    mode: i8,
    braking: Option<state::After>,
    error_code: u16,
    motion: Motion,
    demand: Demand,
    motor: motor::Motor,
    /// Position actual = raw count + shift (homing moves the reference).
    shift: i64,
    halted: bool,
    pp: modes::ProfilePosition,
    pv: modes::ProfileVelocity,
    cyclic: modes::Cyclic,
    follow: modes::Following,
    homing: homing::Homing,
    forced: [Option<bool>; 32],
    /// 0x60FD at the previous tick.
    inputs_prev: u32,
    /// The SYNC cycle the network runs, when it gives one ([`Drive::set_sync_cycle`]).
    sync_cycle: Option<Duration>,
    /// The kinds of limit logged since the mode started (`limits::Kind` bits).
    reported: u32,
    /// The limits logged, for [`Drive::poll_limit`].
    limits: std::collections::VecDeque<Limited>,
}

impl Drive {
    /// The drive of axis `axis` (0..8; objects at 0x6000 + 0x800 · axis, CiA 402-2 multi-axis
    /// devices) when `dict` has that axis's 0x6040 and 0x6041 (UNSIGNED16 at sub-index 0); `None`
    /// otherwise. Its parameters start at the dictionary's current values; objects the dictionary
    /// lacks take this drive's defaults. The drive starts in Not ready to switch on at `now`.
    pub fn from_dictionary(
        dict: &Dictionary,
        axis: u8,
        config: DriveConfig,
        now: Instant,
    ) -> Option<Drive> {
        if !Drive::axes(dict).contains(&axis) {
            return None;
        }
        let base = 0x6000 + 0x800 * u16::from(axis);
        let params = objects::Params::load(dict, base, &config.motor);
        let process_types = objects::PROCESS
            .iter()
            .map(|&(index, ty)| {
                let ty = dict
                    .entry(objects::at(base, index), 0)
                    .map_or(ty, |e| e.data_type);
                (index, ty)
            })
            .collect();
        let mut supported =
            objects::declared_modes(dict, base, config.sync_clock) & IMPLEMENTED_MODES;
        if config.motor.kind == MotorKind::Stepper {
            supported &= !(1 << 9);
        }
        let tick_ns = u64::try_from(config.tick.as_nanos())
            .unwrap_or(u64::MAX)
            .max(1000);
        let cpr = Drive::cpr_of(&params);
        let motor = motor::Motor::new(&config.motor, cpr);
        let mut drive = Drive {
            axis,
            config,
            tick_ns,
            grid: now,
            ticks: 0,
            touched: false,
            power_on: params.clone(),
            params,
            process_types,
            supported,
            state: State::NotReadyToSwitchOn,
            control: 0,
            mode: 0,
            braking: None,
            error_code: 0,
            motion: Motion::Free,
            demand: Demand::default(),
            motor,
            shift: 0,
            halted: false,
            pp: modes::ProfilePosition::default(),
            pv: modes::ProfileVelocity::default(),
            cyclic: modes::Cyclic::default(),
            follow: modes::Following::default(),
            homing: homing::Homing::default(),
            forced: [None; 32],
            inputs_prev: 0,
            sync_cycle: None,
            reported: 0,
            limits: std::collections::VecDeque::new(),
        };
        drive.power_up(now);
        Some(drive)
    }

    /// The axes (0..8) whose 0x6040 and 0x6041 (UNSIGNED16 at sub-index 0) `dict` has.
    pub fn axes(dict: &Dictionary) -> Vec<u8> {
        (0u8..8)
            .filter(|&a| {
                let base = 0x6000 + 0x800 * u16::from(a);
                [0x6040, 0x6041].iter().all(|&i| {
                    dict.entry(objects::at(base, i), 0)
                        .is_ok_and(|e| e.data_type == od::types::DataType::Unsigned16)
                })
            })
            .collect()
    }

    /// Power-on state (transition 0) at `now`, with the parameters as they are.
    fn power_up(&mut self, now: Instant) {
        self.grid = now;
        self.ticks = 0;
        self.touched = false;
        self.state = State::NotReadyToSwitchOn;
        self.control = 0;
        let mode = self.params.get(objects::P::Mode);
        self.mode = if self.mode_supported(mode) {
            mode as i8
        } else {
            0
        };
        self.braking = None;
        self.error_code = 0;
        self.motion = Motion::Free;
        self.demand = Demand {
            p: self.motor.pos,
            v: self.motor.vel,
        };
        self.shift = 0;
        self.halted = false;
        self.pp = modes::ProfilePosition::default();
        self.pv = modes::ProfileVelocity::default();
        self.cyclic = modes::Cyclic::default();
        self.follow = modes::Following::default();
        self.homing = homing::Homing::default();
        self.motor.cpr = Drive::cpr_of(&self.params);
        self.inputs_prev = self.digital_inputs();
    }

    /// Counts per revolution from 0x608F (or the motor's configuration, which `params` carries).
    fn cpr_of(params: &objects::Params) -> f64 {
        let inc = params.get(objects::P::EncoderIncrements).max(1) as f64;
        let rev = params.get(objects::P::MotorRevolutions).max(1) as f64;
        (inc / rev).round().max(1.0)
    }

    /// NMT reset node: power-on values again (the parameters as the dictionary had them when the
    /// drive was made), Not ready to switch on at `now`. The rotor stays where it is (and coasts
    /// if it moves); 0x6064 reads the raw count again (a home found before is forgotten).
    pub fn reset(&mut self, now: Instant) {
        self.params = self.power_on.clone();
        self.power_up(now);
    }

    /// SYNC (CANopen) or SYNC0 (EtherCAT DC) at `now`: runs the ticks up to `now`, then the cyclic
    /// synchronous modes take their targets (CiA 402-2, cyclic synchronous position/velocity/torque
    /// modes). csp: 0x607A + 0x60B0 (clamped to 0x607D), reached along a straight line one
    /// interpolation period later (0x60C2 when the dictionary has it, else the time since the
    /// previous SYNC); csv: 0x60FF + 0x60B1, the velocity ramped over the same period; cst: 0x6071 +
    /// 0x60B2 ‰ of 0x6076, from then on. 0x60B1 and 0x60B2 also feed forward in csp (and 0x60B2 in
    /// csv).
    pub fn sync(&mut self, now: Instant) {
        self.advance(now);
        self.on_sync(now);
    }

    /// Runs the control ticks up to `now`.
    pub fn handle_timeout(&mut self, now: Instant) {
        self.advance(now);
    }

    /// When the drive needs [`Drive::handle_timeout`] next: the next tick, or `None` while it
    /// stands idle with its power stage off and no write has reached it since.
    pub fn poll_timeout(&self) -> Option<Instant> {
        // An input that reached the idle drive is seen at the next tick, so that the node, which
        // checks its event-driven TPDOs at the application's ticks, sends what it changed.
        if !self.quiescent() || self.touched {
            Some(self.instant(self.ticks + 1))
        } else {
            None
        }
    }

    /// The cycle of the SYNC events as the network runs them, when it runs them on a clock of its
    /// own (EtherCAT: the SYNC0 cycle of the Distributed Clock); `None` when it does not. While set,
    /// the cyclic synchronous modes interpolate each target over it instead of 0x60C2 or the
    /// measured time between two SYNCs: the set-points come at that cycle, whatever 0x60C2 says.
    pub fn set_sync_cycle(&mut self, cycle: Option<Duration>) {
        self.sync_cycle = cycle.filter(|c| !c.is_zero());
    }

    /// Raises a fault with error code `code` at `now` (a simulated device fault: over-temperature
    /// 0x4310, over-voltage 0x3210, …): transition 13 and the fault reaction of 0x605E.
    pub fn raise_fault(&mut self, now: Instant, code: u16) {
        // An idle drive asks for its next tick too, so that whoever runs it sees the fault then.
        self.input_at(now);
        self.fault(code);
    }

    /// Forces 0x60FD bit `bit` (0..32) to `level` at `now` (the drive runs up to `now` first);
    /// `None` follows the simulated switches again (bits 0–2; the others read 0).
    pub fn set_input(&mut self, now: Instant, bit: u8, level: Option<bool>) {
        self.input_at(now);
        if let Some(slot) = self.forced.get_mut(usize::from(bit)) {
            *slot = level;
        }
    }

    /// Every forced 0x60FD bit follows the simulated switches again (as at power-on), with no
    /// tick asked for: what a reset of the device does before [`Drive::reset`].
    pub fn release_inputs(&mut self) {
        self.forced.iter_mut().for_each(|slot| *slot = None);
    }

    /// The axis (0..8).
    pub fn axis(&self) -> u8 {
        self.axis
    }

    /// The instant of the last tick processed.
    pub fn now(&self) -> Instant {
        self.instant(self.ticks)
    }

    /// The state of the state machine.
    pub fn state(&self) -> State {
        self.state
    }

    /// 0x6041 status word.
    pub fn status_word(&self) -> u16 {
        self.compose_status_word()
    }

    /// The control word last written (0x6040).
    pub fn control_word(&self) -> u16 {
        self.control
    }

    /// 0x603F error code; 0 when none.
    pub fn error_code(&self) -> u16 {
        self.error_code
    }

    /// 0x6061 modes of operation display.
    pub fn mode(&self) -> i8 {
        self.mode
    }

    /// The modes 0x6060 accepts, as 0x6502 bits: those the dictionary declares (or whose objects it
    /// has) and this drive implements ([`IMPLEMENTED_MODES`]; no cyclic synchronous torque on a
    /// stepper).
    pub fn supported_modes(&self) -> u32 {
        self.supported
    }

    /// 0x6064 position actual (also 0x6063).
    pub fn position(&self) -> i64 {
        self.actual_raw().round() as i64 + self.shift
    }

    /// 0x6062 position demand (also 0x60FC).
    pub fn position_demand(&self) -> i64 {
        self.set_point().p.round() as i64 + self.shift
    }

    /// 0x60F4 following error actual: position demand − position actual.
    pub fn following_error(&self) -> i64 {
        self.position_demand() - self.position()
    }

    /// 0x606C velocity actual, counts/s.
    pub fn velocity(&self) -> i64 {
        self.reported_velocity_f64().round() as i64
    }

    /// 0x606B velocity demand, counts/s.
    pub fn velocity_demand(&self) -> i64 {
        self.set_point().v.round() as i64
    }

    /// 0x6077 torque actual, per mille of the rated torque (0x6074 reads the same).
    pub fn torque(&self) -> i16 {
        let permille = self.motor.torque / self.rated_torque() * 1000.0;
        permille
            .round()
            .clamp(f64::from(i16::MIN), f64::from(i16::MAX)) as i16
    }

    /// 0x60FD digital inputs: bit 0 negative limit switch, bit 1 positive limit switch, bit 2 home
    /// switch, as simulated or forced.
    pub fn digital_inputs(&self) -> u32 {
        let count = self.motor.count();
        let mut bits = 0u32;
        for bit in 0u8..32 {
            let level = match self.forced[usize::from(bit)] {
                Some(level) => level,
                None => switches::switch(&self.config.sim, bit).is_some_and(|s| s.active(count)),
            };
            if level {
                bits |= 1 << bit;
            }
        }
        bits
    }

    /// The homing status (CiA 402-2 homing mode, status word bits 10, 12, 13).
    pub fn homing_status(&self) -> HomingStatus {
        self.homing.status
    }

    /// The rotor's position in raw counts (the physical position the switches are placed in).
    pub fn rotor_position(&self) -> f64 {
        self.motor.pos
    }

    /// The configuration.
    pub fn config(&self) -> &DriveConfig {
        &self.config
    }

    /// The simulated machine, to move its switches at run time (positions in raw counts).
    pub fn sim_mut(&mut self) -> &mut SimConfig {
        &mut self.config.sim
    }

    // ----- internals shared by the parts -----

    /// The first index of this axis's objects.
    fn base(&self) -> u16 {
        0x6000 + 0x800 * u16::from(self.axis)
    }

    fn instant(&self, tick: u64) -> Instant {
        self.grid + Duration::from_nanos(tick.saturating_mul(self.tick_ns))
    }

    /// The tick, seconds.
    fn dt(&self) -> f64 {
        self.tick_ns as f64 / 1e9
    }

    /// Nanoseconds from tick `origin` to the last tick processed.
    fn since(&self, origin: u64) -> u64 {
        self.ticks
            .saturating_sub(origin)
            .saturating_mul(self.tick_ns)
    }

    /// Whether at least `ms` milliseconds lie between tick `since` and the last tick processed.
    fn held_for(&self, since: u64, ms: u64) -> bool {
        u128::from(self.ticks.saturating_sub(since)) * u128::from(self.tick_ns)
            >= u128::from(ms) * 1_000_000
    }

    /// The rated torque, N·m.
    fn rated_torque(&self) -> f64 {
        (self.params.get(objects::P::RatedTorque).max(1) as f64) / 1000.0
    }

    /// The torque limit, N·m (0x6072 per mille of 0x6076).
    fn torque_limit(&self) -> f64 {
        self.params.get(objects::P::MaxTorque).max(0) as f64 / 1000.0 * self.rated_torque()
    }

    /// The actual position in raw counts as the drive sees it (the rotor, or the commanded steps of
    /// a stepper without encoder).
    fn actual_raw(&self) -> f64 {
        if self.open_loop() {
            self.demand.p
        } else {
            self.motor.pos
        }
    }

    fn reported_velocity_f64(&self) -> f64 {
        if self.open_loop() {
            self.demand.v
        } else {
            self.motor.vel
        }
    }

    fn open_loop(&self) -> bool {
        self.config.motor.kind == MotorKind::Stepper && !self.config.motor.encoder
    }

    /// Replaces the motion by `profile` from the present tick.
    fn plan(&mut self, profile: profile::Profile) {
        self.motion = Motion::Plan {
            profile,
            origin: self.ticks,
        };
    }

    /// Whether the demand has reached its final state (a finished plan, holding, or power off).
    fn plan_done(&self) -> bool {
        match &self.motion {
            Motion::Plan { profile, origin } => profile.finished(self.since(*origin)),
            Motion::Hold | Motion::Free => true,
            _ => false,
        }
    }

    /// Whether the demand stands still.
    fn standstill(&self) -> bool {
        self.plan_done() && self.demand.v == 0.0
    }

    /// Idle: nothing moves and nothing will change until an input arrives.
    fn quiescent(&self) -> bool {
        matches!(
            self.state,
            State::SwitchOnDisabled | State::ReadyToSwitchOn | State::SwitchedOn | State::Fault
        ) && self.braking.is_none()
            && self.motor.vel == 0.0
            && self.level_is_idle()
    }

    /// An input arrives at `now`: the drive runs up to it, and an idle drive asks for its next tick.
    fn input_at(&mut self, now: Instant) {
        self.advance(now);
        if self.quiescent() {
            self.touched = true;
        }
    }

    /// Runs the ticks up to `now`.
    fn advance(&mut self, now: Instant) {
        let last = (now.saturating_duration_since(self.grid).as_nanos() / u128::from(self.tick_ns))
            .min(u128::from(u64::MAX)) as u64;
        if last > self.ticks {
            self.touched = false;
        }
        while self.ticks < last {
            if self.quiescent() {
                self.ticks = last;
                break;
            }
            self.step();
        }
    }

    /// One control tick.
    fn step(&mut self) {
        self.ticks += 1;
        if self.state == State::NotReadyToSwitchOn {
            // Transition 1: initialisation done.
            self.state = State::SwitchOnDisabled;
        }
        self.apply_level();
        self.update_halt();
        let before = self.demand;
        self.cyclic.reference = None;
        let count_before = self.motor.count();
        let dt = self.dt();
        let t_max = self.torque_limit();
        let cmd = if !self.powered() {
            motor::Cmd::Off
        } else {
            // Powered, the motion is never `Free`: entering a powered state starts one.
            match &self.motion {
                Motion::Torque { permille } => motor::Cmd::Torque {
                    tau: permille / 1000.0 * self.rated_torque(),
                    t_max,
                },
                _ => {
                    let next = self.eval_demand(before);
                    let next = self.limit_demand(before, next);
                    let (v_extra, t_extra) = self.feed_forward();
                    self.demand = next;
                    motor::Cmd::Follow {
                        p0: before.p,
                        v0: before.v,
                        p1: next.p,
                        v1: next.v,
                        v_extra,
                        t_extra,
                        t_max,
                    }
                }
            }
        };
        self.motor.step(dt, cmd);
        self.report_excess();
        if !self.powered() || matches!(self.motion, Motion::Torque { .. }) {
            // Nothing drives the demand: it follows the rotor.
            self.demand = Demand {
                p: self.motor.pos,
                v: self.motor.vel,
            };
        }
        let count = self.motor.count();
        if self.state == State::OperationEnabled && self.mode == modes::HM {
            self.homing_tick(count_before, count);
        }
        self.supervise();
        self.mode_tick();
        self.finish_braking();
        self.inputs_prev = self.digital_inputs();
    }

    /// The demand of the cyclic synchronous segment in progress at `now`, an instant at or after
    /// the last tick processed (a SYNC between two ticks); the last tick's demand otherwise.
    fn demand_at(&self, now: Instant) -> Demand {
        match &self.motion {
            Motion::Position {
                from,
                to,
                at,
                period,
            } => {
                let period_ns = period.as_nanos().max(1) as f64;
                let frac = now.saturating_duration_since(*at).as_nanos() as f64 / period_ns;
                if frac <= 1.0 {
                    Demand {
                        p: from + (to - from) * frac,
                        v: (to - from) / (period_ns / 1e9),
                    }
                } else {
                    Demand { p: *to, v: 0.0 }
                }
            }
            Motion::Velocity {
                from,
                to,
                at,
                period,
            } => {
                let frac = (now.saturating_duration_since(*at).as_nanos() as f64
                    / period.as_nanos().max(1) as f64)
                    .min(1.0);
                Demand {
                    p: self.demand.p,
                    v: from + (to - from) * frac,
                }
            }
            _ => self.demand,
        }
    }

    /// The demand at the present tick, from `before` (the demand at the previous one).
    fn eval_demand(&self, before: Demand) -> Demand {
        let dt = self.dt();
        match &self.motion {
            Motion::Plan { profile, origin } => {
                let (p, v) = profile.eval(self.since(*origin));
                Demand { p, v }
            }
            Motion::Position { .. } => self.demand_at(self.instant(self.ticks)),
            Motion::Velocity {
                from,
                to,
                at,
                period,
            } => {
                let t = self.instant(self.ticks).saturating_duration_since(*at);
                let frac = (t.as_nanos() as f64 / period.as_nanos().max(1) as f64).min(1.0);
                let v = from + (to - from) * frac;
                Demand {
                    p: before.p + 0.5 * (before.v + v) * dt,
                    v,
                }
            }
            Motion::Hold | Motion::Free | Motion::Torque { .. } => Demand {
                p: before.p,
                v: 0.0,
            },
        }
    }
}
