//! The rig the SMD indexer tests share: a unit and a master exchanging process data every 1 ms.
#![allow(dead_code)]

use std::time::{Duration, Instant};

use ds402::smd::config::{Configuration, EncoderKind};
use ds402::smd::indexer::{cmd0, cmd1, stat0, Indexer, Inputs, Outputs};

pub const MS: Duration = Duration::from_millis(1);

/// An assembled-move segment: (position, velocity, acceleration, deceleration).
pub type Seg = (i32, u32, u16, u16);

/// A unit with the default configuration and a master that exchanges data every 1 ms.
pub struct Rig {
    pub ix: Indexer,
    pub out: Outputs,
    pub last: Inputs,
}

impl Rig {
    pub fn new() -> Rig {
        Rig::with(Configuration::default())
    }

    pub fn with(config: Configuration) -> Rig {
        let mut ix = Indexer::new(EncoderKind::Incremental, config);
        ix.start(Instant::now(), MS);
        let out = Outputs::default();
        let last = ix.cycle(out, MS);
        Rig { ix, out, last }
    }

    /// CFG_Word_0 `cfg0` (the rest default), the driver enabled, the move parameters `velocity`,
    /// `accel`, `decel`, the position preset to 0 (valid), CMD_word0 back at 0.
    pub fn ready_with(cfg0: u16, velocity: u32, accel: u16, decel: u16) -> Rig {
        let mut r = Rig::with(Configuration {
            cfg0,
            ..Configuration::default()
        });
        r.out = Outputs {
            cmd1: cmd1::ENABLE_DRIVER,
            velocity,
            acceleration: accel,
            deceleration: decel,
            ..Outputs::default()
        };
        r.command(cmd0::PRESET_POSITION);
        r.command(0);
        assert_eq!(r.s0() & stat0::POSITION_INVALID, 0);
        r
    }

    /// Driver enabled, position preset to 0 (valid), move parameters set, and a move of 100 steps out
    /// and back just completed: Motor_Position 0 with Move_Complete 1, so that a test sees whether
    /// what it does resets Move_Complete (SMD-R6-057). CMD_word0 back at 0.
    pub fn ready() -> Rig {
        let mut r = Rig::ready_with(0, 10_000, 10, 10);
        r.command(cmd0::RESET_ERRORS);
        r.command(0);
        r.move_to_end(cmd0::RELATIVE_MOVE, 100);
        r.move_to_end(cmd0::RELATIVE_MOVE, -100);
        assert_eq!(r.pos(), 0);
        assert_eq!(
            r.s0() & (stat0::POSITION_INVALID | stat0::MOVE_COMPLETE | stat0::COMMAND_ERROR),
            stat0::MOVE_COMPLETE
        );
        r
    }

    /// The instant of the last exchange: the start plus the time steps of the cycles so far.
    pub fn now(&self) -> Instant {
        self.ix.last_exchange().expect("the rig starts the indexer")
    }

    pub fn cycle(&mut self) -> Inputs {
        self.last = self.ix.cycle(self.out, MS);
        self.last
    }

    /// Writes CMD_word0 = `c` for one cycle.
    pub fn command(&mut self, c: u16) -> Inputs {
        self.out.cmd0 = c;
        self.cycle()
    }

    pub fn s0(&self) -> u16 {
        self.last.status0
    }

    pub fn s1(&self) -> u16 {
        self.last.status1
    }

    pub fn pos(&self) -> i32 {
        self.last.motor_position
    }

    /// Cycles until `f` holds (at most `max` cycles); the number of cycles it took.
    pub fn until(&mut self, max: u32, f: impl Fn(&Inputs) -> bool) -> u32 {
        for n in 1..=max {
            if f(&self.cycle()) {
                return n;
            }
        }
        panic!("not within {max} cycles; last {:?}", self.last);
    }

    /// A Relative (or Absolute) move of `position` run to its end; CMD_word0 back to 0.
    pub fn move_to_end(&mut self, c: u16, position: i32) -> u32 {
        self.out.position = position;
        self.command(c);
        let n = self.until(600_000, |i| i.status0 & stat0::STOPPED != 0);
        self.command(0);
        n
    }

    /// A Relative move of `position` run for `ms` cycles, then held: Hold_Move until Stopped,
    /// CMD_word0 back at 0.
    pub fn hold_a_move(&mut self, position: i32, ms: u32) {
        self.out.position = position;
        self.command(cmd0::RELATIVE_MOVE);
        for _ in 0..ms {
            self.cycle();
        }
        self.command(cmd0::HOLD_MOVE);
        self.until(5_000, |i| i.status0 & stat0::STOPPED != 0);
        self.command(0);
    }

    /// The programming routine of R2 (p.41): First Block, then one Segment Block handshake per
    /// segment, then Program_Assembled back to 0 (with Save_to_Flash when `save`). Returns
    /// STATUS_word0 after each step.
    pub fn program(&mut self, segments: &[Seg], save: bool) -> Vec<u16> {
        let mut seen = Vec::new();
        self.command(cmd0::PROGRAM_ASSEMBLED);
        seen.push(self.s0());
        for &(position, velocity, acceleration, deceleration) in segments {
            self.out.position = position;
            self.out.velocity = velocity;
            self.out.acceleration = acceleration;
            self.out.deceleration = deceleration;
            self.command(cmd0::PROGRAM_ASSEMBLED | cmd0::READ_ASSEMBLED_DATA);
            seen.push(self.s0());
            self.command(cmd0::PROGRAM_ASSEMBLED);
            seen.push(self.s0());
        }
        if save {
            self.out.cmd1 |= cmd1::SAVE_TO_FLASH;
        }
        self.command(0);
        seen.push(self.s0());
        self.out.cmd1 &= !cmd1::SAVE_TO_FLASH;
        seen
    }
}
