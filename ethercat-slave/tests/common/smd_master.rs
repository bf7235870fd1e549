//! A master of one SMD23K-B on the emulated chain, in process: EtherCAT frames only (the start-up of
//! `common::master`, one LRW of the 20 output bytes per 1 ms cycle, an LRD of the 20 input bytes
//! after it), with the bytes laid out by hand as Reference 6 gives them (SMD-R6-001: CMD_word0,
//! CMD_word1, Position, Velocity, Acceleration, Deceleration, Motor_Current, Jerk at byte 0, 2, 4, 8,
//! 12, 14, 16, 18; SMD-R6-002: STATUS_word0, STATUS_word1, Motor_Position, Encoder_Position,
//! Trapped_Encoder_Position, Motor_Current, Jerk at byte 0, 2, 4, 8, 12, 16, 18).

#![allow(dead_code)]

use std::time::{Duration, Instant};

use ethercat_slave::esc::al::state;
use ethercat_slave::esc::cmd;
use ethercat_slave::frame::Datagram;
use ethercat_slave::master::SimChain;
use ethercat_slave::smd::binding::Device;
use ethercat_slave::smd::SmdChain;

use crate::common::master::{al, bring_up, one, request};

/// The 20 output bytes a master writes, word by word.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Out {
    pub cmd0: u16,
    pub cmd1: u16,
    pub position: i32,
    pub velocity: u32,
    pub acceleration: u16,
    pub deceleration: u16,
    pub motor_current: u16,
    pub jerk: u16,
}

impl Out {
    /// The 20 bytes, little-endian at the offsets of SMD-R6-001.
    pub fn bytes(&self) -> [u8; 20] {
        let mut b = [0u8; 20];
        b[0..2].copy_from_slice(&self.cmd0.to_le_bytes());
        b[2..4].copy_from_slice(&self.cmd1.to_le_bytes());
        b[4..8].copy_from_slice(&self.position.to_le_bytes());
        b[8..12].copy_from_slice(&self.velocity.to_le_bytes());
        b[12..14].copy_from_slice(&self.acceleration.to_le_bytes());
        b[14..16].copy_from_slice(&self.deceleration.to_le_bytes());
        b[16..18].copy_from_slice(&self.motor_current.to_le_bytes());
        b[18..20].copy_from_slice(&self.jerk.to_le_bytes());
        b
    }
}

/// The 20 input bytes a master reads, word by word.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct In {
    pub status0: u16,
    pub status1: u16,
    pub motor_position: i32,
    pub encoder_position: i32,
    pub trapped_encoder_position: i32,
    pub motor_current: u16,
    pub jerk: u16,
}

impl In {
    /// From the 20 bytes at the offsets of SMD-R6-002.
    pub fn of(b: &[u8]) -> In {
        let u16_at = |o: usize| u16::from_le_bytes([b[o], b[o + 1]]);
        let i32_at = |o: usize| i32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
        In {
            status0: u16_at(0),
            status1: u16_at(2),
            motor_position: i32_at(4),
            encoder_position: i32_at(8),
            trapped_encoder_position: i32_at(12),
            motor_current: u16_at(16),
            jerk: u16_at(18),
        }
    }
}

/// One unit and its master.
pub struct Master {
    pub c: SimChain,
    /// The chain's power-on.
    pub t0: Instant,
    /// What the next LRW writes.
    pub out: Out,
    /// What the last LRD read.
    pub last: In,
}

/// 1 ms.
pub const MS: Duration = Duration::from_millis(1);

impl Master {
    /// One SMD23K-B powered on now, in Init, its process-data cycle the master's: 1 ms (the
    /// indexer's exchanges fall due when the master's frames come).
    pub fn new() -> Master {
        let t0 = Instant::now();
        let chain = SmdChain::new(Device::Smd23kB, 1, MS, t0).unwrap();
        let c = SimChain::with_chain(chain, t0);
        Master {
            c,
            t0,
            out: Out::default(),
            last: In::default(),
        }
    }

    /// Configured and brought to Safe-Op, no output image written yet.
    pub fn safe_op() -> Master {
        let mut m = Master::new();
        bring_up(&mut m.c, state::SAFEOP);
        assert_eq!(al(&mut m.c, 0), (0x0004, 0), "Safe-Op");
        m
    }

    /// Requests Op; the unit is in it.
    pub fn request_op(&mut self) {
        request(&mut self.c, state::OP);
        assert_eq!(al(&mut self.c, 0), (0x0008, 0), "Op");
    }

    /// In Op with the outputs all 0, written in Safe-Op and then in Op once (the edge reference,
    /// SMD-R6-073), then Enable_Driver (CMD_word1 = 0x8000) for one more cycle.
    pub fn op() -> Master {
        let mut m = Master::safe_op();
        m.lrw();
        m.request_op();
        m.lrw();
        m.out.cmd1 = 0x8000;
        m.lrw();
        m
    }

    /// The LRW of the 20 output bytes (the unit's output FMMU at logical 0, the input FMMU at 20),
    /// without a cycle; its working counter.
    pub fn write(&mut self) -> u16 {
        let mut data = self.out.bytes().to_vec();
        data.resize(40, 0);
        let d = Datagram {
            cmd: cmd::LRW,
            index: 0,
            address: 0,
            data,
            wkc: 0,
        };
        one(&mut self.c, d).wkc
    }

    /// The LRD of the 20 input bytes at logical 20.
    pub fn read(&mut self) -> In {
        let d = Datagram {
            cmd: cmd::LRD,
            index: 0,
            address: 20,
            data: vec![0; 20],
            wkc: 0,
        };
        let r = one(&mut self.c, d);
        assert_eq!(r.wkc, 1, "the input FMMU is read");
        self.last = In::of(&r.data);
        self.last
    }

    /// One cycle: the LRW of `out`, 1 ms of the unit's time, the LRD of the inputs it answers.
    pub fn lrw(&mut self) -> In {
        self.write();
        self.c.cycle(MS);
        self.read()
    }

    /// CMD_word0 = `cmd0` for one cycle.
    pub fn command(&mut self, cmd0: u16) -> In {
        self.out.cmd0 = cmd0;
        self.lrw()
    }

    /// `n` cycles with the same outputs; the inputs of the last.
    pub fn run(&mut self, n: u32) -> In {
        assert!(n > 0);
        for _ in 0..n {
            self.lrw();
        }
        self.last
    }

    /// 1 ms of the unit's time without a frame.
    pub fn silence(&mut self) {
        self.c.cycle(MS);
    }

    /// Milliseconds since power-on, by the master's clock.
    pub fn ms(&self) -> u128 {
        (self.c.now - self.t0).as_millis()
    }

    /// STATUS_word1 bit 11, Heartbeat_Bit, as the last inputs carry it: it changes state every
    /// 500 ms in Command Mode (SMD-R6-067), 0 for the first 500 ms after power-on.
    pub fn heartbeat(&self) -> u16 {
        if (self.ms() / 500) % 2 == 1 {
            0x0800
        } else {
            0
        }
    }
}
