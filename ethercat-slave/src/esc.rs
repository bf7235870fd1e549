//! One slave's ESC: its memory (registers 0x0000–0x0FFF and process RAM up to 64 KiB), its
//! configured station address (0x0010) and alias (0x0012), and the datagram commands of ETG.1000.4
//! §5.4 with their working-counter rules. A [`Chain`] passes a frame through its slaves in order.
//!
//! Working counter: a read that a slave serves adds 1, a write 1, a read-write 1 for the read and 2
//! for the write (3 when both); a broadcast adds per slave; ARMW/FRMW add 1 at the slave that reads and
//! 1 at each slave that writes. Auto-increment addressing: each slave takes the datagram when its ADP
//! is 0 and increments ADP as the frame passes.

use crate::frame::{datagrams, FrameError};

/// Commands (ETG.1000.4 Table 14).
pub mod cmd {
    /// No operation.
    pub const NOP: u8 = 0;
    /// Auto-increment read.
    pub const APRD: u8 = 1;
    /// Auto-increment write.
    pub const APWR: u8 = 2;
    /// Auto-increment read-write.
    pub const APRW: u8 = 3;
    /// Configured-address read.
    pub const FPRD: u8 = 4;
    /// Configured-address write.
    pub const FPWR: u8 = 5;
    /// Configured-address read-write.
    pub const FPRW: u8 = 6;
    /// Broadcast read.
    pub const BRD: u8 = 7;
    /// Broadcast write.
    pub const BWR: u8 = 8;
    /// Broadcast read-write.
    pub const BRW: u8 = 9;
    /// Logical read.
    pub const LRD: u8 = 10;
    /// Logical write.
    pub const LWR: u8 = 11;
    /// Logical read-write.
    pub const LRW: u8 = 12;
    /// Auto-increment read, multiple write.
    pub const ARMW: u8 = 13;
    /// Configured-address read, multiple write.
    pub const FRMW: u8 = 14;
}

/// ESC memory size.
pub const MEMORY: usize = 0x1_0000;
/// Configured station address register.
pub const STATION_ADDRESS: u16 = 0x0010;
/// Configured station alias register.
pub const STATION_ALIAS: u16 = 0x0012;

/// First FMMU register block (16 bytes each, ETG.1000.4 Table 57).
pub const FMMU_BASE: u16 = 0x0600;
/// FMMUs an ESC has here.
pub const FMMUS: usize = 16;
/// EEPROM (SII) control/status register.
pub const EEPROM_CONTROL: u16 = 0x0502;
/// EEPROM word address register.
pub const EEPROM_ADDRESS: u16 = 0x0504;
/// EEPROM data register (8 bytes are read at once).
pub const EEPROM_DATA: u16 = 0x0508;

/// One FMMU as the master configured it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fmmu {
    /// Logical start address.
    pub logical: u32,
    /// Length in bytes.
    pub len: u16,
    /// Physical start address.
    pub physical: u16,
    /// Maps reads (LRD/LRW) from the slave.
    pub read: bool,
    /// Maps writes (LWR/LRW) to the slave.
    pub write: bool,
}

/// One slave controller.
#[derive(Clone)]
pub struct Esc {
    mem: Vec<u8>,
    /// The SII EEPROM image, read through the EEPROM interface registers.
    pub sii: Vec<u8>,
    /// What the AL state transitions check.
    pub al: crate::al::AlConfig,
}

impl Default for Esc {
    fn default() -> Self {
        Esc::new()
    }
}

impl std::fmt::Debug for Esc {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Esc")
            .field("station_address", &self.station_address())
            .finish()
    }
}

/// How one slave acts on a datagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Access {
    Read,
    Write,
    ReadWrite,
    /// ARMW/FRMW: read at the addressed slave, write at the others.
    ReadMultipleWrite,
}

impl Esc {
    /// An ESC with zeroed memory (station address 0).
    pub fn new() -> Esc {
        let mut esc = Esc {
            mem: vec![0; MEMORY],
            sii: Vec::new(),
            al: crate::al::AlConfig::default(),
        };
        esc.store(crate::al::AL_STATUS, &[crate::al::state::INIT, 0]);
        esc
    }

    /// The configured station address (register 0x0010).
    pub fn station_address(&self) -> u16 {
        self.read_u16(STATION_ADDRESS)
    }

    /// The AL state (AL status bits 0–3) and whether the error indicator is set.
    pub fn al_state(&self) -> (u8, bool) {
        let s = self.read_u16(crate::al::AL_STATUS);
        ((s & 0x0F) as u8, s & 0x10 != 0)
    }

    /// A 16-bit register.
    pub fn read_u16(&self, at: u16) -> u16 {
        let a = usize::from(at);
        u16::from_le_bytes([self.mem[a], self.mem[(a + 1) % MEMORY]])
    }

    /// Sets memory from the slave's side (the application).
    pub fn store(&mut self, at: u16, bytes: &[u8]) {
        for (k, b) in bytes.iter().enumerate() {
            self.mem[(usize::from(at) + k) % MEMORY] = *b;
        }
    }

    /// Memory as the master sees it.
    pub fn load(&self, at: u16, len: usize) -> Vec<u8> {
        (0..len)
            .map(|k| self.mem[(usize::from(at) + k) % MEMORY])
            .collect()
    }

    /// Reads into `data` (ORed for broadcasts, as an ESC ORs a broadcast read).
    fn read_into(&self, ado: u16, data: &mut [u8], or: bool) {
        for (k, d) in data.iter_mut().enumerate() {
            let m = self.mem[(usize::from(ado) + k) % MEMORY];
            *d = if or { *d | m } else { m };
        }
    }

    fn write_from(&mut self, ado: u16, data: &[u8]) {
        self.store(ado, data);
        self.after_write(ado, data.len());
    }

    /// What a master's write triggers: an EEPROM read command loads 8 bytes of the SII image at the
    /// word address into the data register (ETG.1000.4 §6.4; command bits 8–10 of 0x0502 = 001).
    fn after_write(&mut self, ado: u16, len: usize) {
        let touches = |reg: u16, n: usize| {
            let (a, b) = (usize::from(ado), usize::from(ado) + len);
            let (r, e) = (usize::from(reg), usize::from(reg) + n);
            a < e && r < b
        };
        if touches(crate::al::AL_CONTROL, 2) {
            let control = self.read_u16(crate::al::AL_CONTROL);
            let status = self.read_u16(crate::al::AL_STATUS);
            let current = (status & 0x0F) as u8;
            let error = status & 0x10 != 0;
            let mem = |at: u16, n: usize| self.load(at, n);
            let (next, code) = crate::al::transition(&self.al, current, error, control, &mem);
            if code == u16::MAX {
                // Error not acknowledged: nothing changes.
            } else if code == crate::al::code::NONE {
                self.store(crate::al::AL_STATUS, &[next, 0]);
                self.store(crate::al::AL_STATUS_CODE, &[0, 0]);
            } else {
                self.store(crate::al::AL_STATUS, &[current | 0x10, 0]);
                self.store(crate::al::AL_STATUS_CODE, &code.to_le_bytes());
            }
        }
        if touches(EEPROM_CONTROL, 2) {
            let control = self.read_u16(EEPROM_CONTROL);
            if (control >> 8) & 0x07 == 0x01 {
                let word = u32::from_le_bytes([
                    self.mem[usize::from(EEPROM_ADDRESS)],
                    self.mem[usize::from(EEPROM_ADDRESS) + 1],
                    self.mem[usize::from(EEPROM_ADDRESS) + 2],
                    self.mem[usize::from(EEPROM_ADDRESS) + 3],
                ]) as usize;
                let bytes: Vec<u8> = (0..8)
                    .map(|k| self.sii.get(word * 2 + k).copied().unwrap_or(0xFF))
                    .collect();
                self.store(EEPROM_DATA, &bytes);
                // Command done, not busy, no error; bit 6 says 8 bytes are read at once.
                let status = 0x0040;
                self.store(EEPROM_CONTROL, &u16::to_le_bytes(status));
            }
        }
    }

    /// FMMU `n` as configured in its registers, when active.
    pub fn fmmu(&self, n: usize) -> Option<Fmmu> {
        let base = FMMU_BASE + 16 * n as u16;
        let r = self.load(base, 16);
        if n >= FMMUS || r[12] & 0x01 == 0 {
            return None;
        }
        Some(Fmmu {
            logical: u32::from_le_bytes([r[0], r[1], r[2], r[3]]),
            len: u16::from_le_bytes([r[4], r[5]]),
            physical: u16::from_le_bytes([r[8], r[9]]),
            read: r[11] & 0x01 != 0,
            write: r[11] & 0x02 != 0,
        })
    }

    /// A logical datagram at `addr` over `data`: mapped reads copied in, mapped writes copied out;
    /// the working-counter increment (1 for a read, 1 for LWR's write, 2 for LRW's write).
    fn logical(&mut self, command: u8, addr: u32, data: &mut [u8]) -> u16 {
        let (want_read, want_write) = match command {
            cmd::LRD => (true, false),
            cmd::LWR => (false, true),
            _ => (true, true),
        };
        let incoming = data.to_vec();
        let (mut read, mut wrote) = (false, false);
        for n in 0..FMMUS {
            let Some(f) = self.fmmu(n) else { continue };
            let start = u64::from(f.logical).max(u64::from(addr));
            let end =
                (u64::from(f.logical) + u64::from(f.len)).min(u64::from(addr) + data.len() as u64);
            if start >= end {
                continue;
            }
            for l in start..end {
                let k = (l - u64::from(addr)) as usize;
                let phys = (u64::from(f.physical) + (l - u64::from(f.logical))) as u16;
                if want_read && f.read {
                    data[k] = self.mem[usize::from(phys)];
                    read = true;
                }
                if want_write && f.write {
                    self.mem[usize::from(phys)] = incoming[k];
                    wrote = true;
                }
            }
        }
        let write_weight = if command == cmd::LRW { 2 } else { 1 };
        u16::from(read) + if wrote { write_weight } else { 0 }
    }

    /// Applies one register datagram the slave is addressed by; the working-counter increment.
    fn access(
        &mut self,
        access: Access,
        ado: u16,
        data: &mut [u8],
        or: bool,
        addressed: bool,
    ) -> u16 {
        match access {
            Access::Read => {
                self.read_into(ado, data, or);
                1
            }
            Access::Write => {
                self.write_from(ado, data);
                1
            }
            Access::ReadWrite => {
                let incoming = data.to_vec();
                self.read_into(ado, data, or);
                self.write_from(ado, &incoming);
                3
            }
            Access::ReadMultipleWrite if addressed => {
                self.read_into(ado, data, false);
                1
            }
            Access::ReadMultipleWrite => {
                self.write_from(ado, data);
                1
            }
        }
    }
}

/// Slaves in the order a frame passes them.
#[derive(Debug, Clone, Default)]
pub struct Chain {
    /// The slaves.
    pub slaves: Vec<Esc>,
}

impl Chain {
    /// `n` slaves with zeroed memory.
    pub fn new(n: usize) -> Chain {
        Chain {
            slaves: (0..n).map(|_| Esc::new()).collect(),
        }
    }

    /// Processes every datagram of `frame` in place, as the frame passes each slave in turn. A frame
    /// that does not parse is left unchanged and the error returned (the caller drops it).
    pub fn process(&mut self, frame: &mut [u8]) -> Result<(), FrameError> {
        let dgs = datagrams(frame)?;
        for esc in self.slaves.iter_mut() {
            for d in &dgs {
                let command = frame[d.start];
                let adp = u16::from_le_bytes([frame[d.start + 2], frame[d.start + 3]]);
                let ado = u16::from_le_bytes([frame[d.start + 4], frame[d.start + 5]]);
                let (access, addressed, auto, or) = match command {
                    cmd::APRD => (Some(Access::Read), adp == 0, true, false),
                    cmd::APWR => (Some(Access::Write), adp == 0, true, false),
                    cmd::APRW => (Some(Access::ReadWrite), adp == 0, true, false),
                    cmd::ARMW => (Some(Access::ReadMultipleWrite), adp == 0, true, false),
                    cmd::FPRD => (
                        Some(Access::Read),
                        adp == esc.station_address(),
                        false,
                        false,
                    ),
                    cmd::FPWR => (
                        Some(Access::Write),
                        adp == esc.station_address(),
                        false,
                        false,
                    ),
                    cmd::FPRW => (
                        Some(Access::ReadWrite),
                        adp == esc.station_address(),
                        false,
                        false,
                    ),
                    cmd::FRMW => (
                        Some(Access::ReadMultipleWrite),
                        adp == esc.station_address(),
                        false,
                        false,
                    ),
                    cmd::BRD => (Some(Access::Read), true, true, true),
                    cmd::BWR => (Some(Access::Write), true, true, false),
                    cmd::BRW => (Some(Access::ReadWrite), true, true, true),
                    cmd::LRD | cmd::LWR | cmd::LRW => {
                        let addr = u32::from_le_bytes([
                            frame[d.start + 2],
                            frame[d.start + 3],
                            frame[d.start + 4],
                            frame[d.start + 5],
                        ]);
                        let (data, wkc_at) = (d.data(), d.wkc());
                        let mut buf = frame[data..data + d.len].to_vec();
                        let inc = esc.logical(command, addr, &mut buf);
                        frame[data..data + d.len].copy_from_slice(&buf);
                        let wkc = u16::from_le_bytes([frame[wkc_at], frame[wkc_at + 1]])
                            .wrapping_add(inc);
                        frame[wkc_at..wkc_at + 2].copy_from_slice(&wkc.to_le_bytes());
                        (None, false, false, false)
                    }
                    // NOP passes unchanged.
                    _ => (None, false, false, false),
                };
                if let Some(access) = access {
                    let multiple = access == Access::ReadMultipleWrite;
                    if addressed || multiple {
                        let (data, wkc_at) = (d.data(), d.wkc());
                        let mut buf = frame[data..data + d.len].to_vec();
                        let inc = esc.access(access, ado, &mut buf, or, addressed);
                        frame[data..data + d.len].copy_from_slice(&buf);
                        let wkc = u16::from_le_bytes([frame[wkc_at], frame[wkc_at + 1]])
                            .wrapping_add(inc);
                        frame[wkc_at..wkc_at + 2].copy_from_slice(&wkc.to_le_bytes());
                    }
                    if auto {
                        // Broadcasts increment ADP too (ETG.1000.4: "position" counts slaves).
                        let next = adp.wrapping_add(1);
                        frame[d.start + 2..d.start + 4].copy_from_slice(&next.to_le_bytes());
                    }
                }
            }
        }
        Ok(())
    }
}
