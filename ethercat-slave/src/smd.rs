//! The SMD23K-B / SMD24K as an EtherCAT slave: an [`Esc`] with the SII image and the AL checks of the
//! fixture's ESI, and the indexer model (`ds402::smd::binding::SmdUnit`) behind it. Each
//! [`SmdChain::cycle`] is the slave's process-data cycle: in Op the 20 output bytes the master wrote
//! into SM2 go to the model; in Safe-Op and Op the model's 20 input bytes are put into SM3. The model
//! sees the EtherCAT state (PreOp_SafeOp, commands only in Op).

use std::time::Duration;

use ds402::smd::binding::{Device, SmdUnit, FIXTURE_ESI, FIXTURE_NAME};
use ds402::smd::config::EncoderKind;
use ds402::smd::indexer::{Inputs, NetworkState, Outputs};

use crate::al::{state, AlConfig};
use crate::esc::{Chain, Esc};
use crate::frame::FrameError;

/// Why a slave could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SmdSlaveError {
    /// The fixture's ESI.
    #[error("the SMD description: {0}")]
    Description(String),
    /// The SII image.
    #[error(transparent)]
    Sii(#[from] od::sii::SiiError),
}

/// The fixture's description of `device`.
pub fn description(device: Device) -> Result<od::DeviceDescription, SmdSlaveError> {
    let select = od::esi::Select::Name(device.order_code().to_string());
    od::esi::read(FIXTURE_ESI.as_bytes(), FIXTURE_NAME, Some(&select))
        .map_err(|e| SmdSlaveError::Description(e.to_string()))
}

/// Decodes the 20 output bytes (0x7000:01–08, packed little-endian).
pub fn decode_outputs(b: &[u8; 20]) -> Outputs {
    let u16_at = |o: usize| u16::from_le_bytes([b[o], b[o + 1]]);
    let u32_at = |o: usize| u32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    Outputs {
        cmd0: u16_at(0),
        cmd1: u16_at(2),
        position: u32_at(4) as i32,
        velocity: u32_at(8),
        acceleration: u16_at(12),
        deceleration: u16_at(14),
        motor_current: u16_at(16),
        jerk: u16_at(18),
    }
}

/// Encodes the 20 input bytes (0x6000:01–07).
pub fn encode_inputs(i: &Inputs) -> [u8; 20] {
    let mut b = [0u8; 20];
    b[0..2].copy_from_slice(&i.status0.to_le_bytes());
    b[2..4].copy_from_slice(&i.status1.to_le_bytes());
    b[4..8].copy_from_slice(&i.motor_position.to_le_bytes());
    b[8..12].copy_from_slice(&i.encoder_position.to_le_bytes());
    b[12..16].copy_from_slice(&i.trapped_encoder_position.to_le_bytes());
    b[16..18].copy_from_slice(&i.motor_current.to_le_bytes());
    b[18..20].copy_from_slice(&i.jerk.to_le_bytes());
    b
}

/// A chain of virtual SMD units.
pub struct SmdChain {
    /// The ESCs in frame order.
    pub chain: Chain,
    /// The model behind each ESC.
    pub units: Vec<SmdUnit>,
    /// SM2 / SM3 start addresses from the ESI.
    outputs_at: u16,
    inputs_at: u16,
}

impl SmdChain {
    /// `n` units of `device`, serial numbers 1…n.
    pub fn new(device: Device, n: usize) -> Result<SmdChain, SmdSlaveError> {
        let desc = description(device)?;
        let ec = desc
            .ethercat
            .as_ref()
            .ok_or_else(|| SmdSlaveError::Description("no EtherCAT part".into()))?;
        let at = |kind: &str| {
            ec.sync_managers
                .iter()
                .find(|s| s.kind == kind)
                .map_or(0, |s| s.start_address)
        };
        let (outputs_at, inputs_at) = (at("Outputs"), at("Inputs"));
        let mut chain = Chain::new(0);
        let mut units = Vec::new();
        for k in 0..n {
            let mut esc = Esc::new();
            esc.sii = od::sii::write(&desc, k as u32 + 1)?;
            esc.al = AlConfig::from_description(&desc);
            chain.slaves.push(esc);
            let mut unit = SmdUnit::new(device, EncoderKind::Incremental)
                .map_err(|e| SmdSlaveError::Description(e.to_string()))?;
            unit.set_network_state(NetworkState::Init);
            units.push(unit);
        }
        Ok(SmdChain {
            chain,
            units,
            outputs_at,
            inputs_at,
        })
    }

    /// Processes a frame as it passes the chain.
    pub fn process(&mut self, frame: &mut [u8]) -> Result<(), FrameError> {
        self.chain.process(frame)
    }

    /// One process-data cycle of every unit, `dt` long.
    pub fn cycle(&mut self, dt: Duration) {
        for (esc, unit) in self.chain.slaves.iter_mut().zip(self.units.iter_mut()) {
            let (al, _) = esc.al_state();
            let network = match al {
                state::OP => NetworkState::Op,
                state::SAFEOP => NetworkState::SafeOp,
                state::PREOP => NetworkState::PreOp,
                _ => NetworkState::Init,
            };
            unit.set_network_state(network);
            if al == state::OP {
                let raw = esc.load(self.outputs_at, 20);
                let mut b = [0u8; 20];
                b.copy_from_slice(&raw);
                unit.write_outputs(&decode_outputs(&b));
            }
            let inputs = unit.cycle(dt);
            if matches!(al, state::OP | state::SAFEOP) {
                esc.store(self.inputs_at, &encode_inputs(&inputs));
            }
        }
    }
}
