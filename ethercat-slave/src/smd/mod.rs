//! The SMD23K-B / SMD24K as an EtherCAT slave: a [`UnitChain`] of [`SmdUnit`]s, each an [`Esc`] with
//! the SII image and the AL checks of the fixture's ESI, the CoE SDO server (`od::coe::server`) on the
//! unit's dictionary behind its mailbox, and the indexer model bound to its dictionary
//! ([`binding::SmdUnit`]) behind its process data. The chain's work (mailboxes, AL states, the
//! watchdog, SYNC0, the process images) is [`crate::unit`]'s; what is the SMD's is here:
//!
//! - the SyncManager watchdog's expiry in Op also sets the model's Input_Error (SMD-R1-035);
//! - SYNC0 events go to the model at their instant (DC_Sync starts); the output bytes of SM2 (in Op)
//!   and the input bytes of SM3 (in Safe-Op and Op) are laid out as the description's PDO assignment
//!   (0x1C12, 0x1C13) and mapping objects (0x1600, 0x1A00) say (20 bytes each);
//! - the model sees the EtherCAT state (PreOp_SafeOp, commands only in Op);
//! - SYNC0 is accepted with a cycle time of 2 ms to 50 ms (SMD-T3-003); outside it Pre-Op → Safe-Op
//!   is refused with AL status code 0x0036.
//!
//! Methods and polling order are [`UnitChain`]'s: [`SmdChain::new`] at `now`, then
//! [`SmdChain::handle_frame`] for every frame, [`SmdChain::handle_timeout`] whenever
//! [`SmdChain::poll_timeout`] has passed.

pub mod binding;

use std::time::{Duration, Instant};

use binding::{Device, SmdUnit, FIXTURE_ESI, FIXTURE_NAME};
use ds402::smd::config::EncoderKind;
use ds402::smd::indexer::NetworkState;
use od::coe::server::CoeServer;
use od::hook::ProcessImage;
use od::sdo::server::ServerConfig;

use crate::esc::al::{AlConfig, AlState, AlStatusCode};
use crate::esc::Esc;
use crate::unit::{Model, SyncEvent, Unit, UnitChain};

/// SYNC0 cycle times the unit accepts, in ns (SMD-T3-003: 2 ms to 50 ms).
pub const SYNC0_CYCLE_RANGE: (u32, u32) = (2_000_000, 50_000_000);

/// Why a slave could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SmdSlaveError {
    /// The fixture's ESI does not read.
    #[error("the SMD description: {0}")]
    Description(#[from] od::ParseError),
    /// The fixture's ESI has no EtherCAT part.
    #[error("the SMD description: no EtherCAT part")]
    NoEthercat,
    /// The unit's dictionary does not bind to the model.
    #[error("the SMD description: {0}")]
    Binding(#[from] binding::BindingError),
    /// The PDO assignment or mapping does not give a process image.
    #[error("the SMD description: {0}")]
    Image(#[from] od::hook::ImageError),
    /// The SII image.
    #[error(transparent)]
    Sii(#[from] od::sii::SiiError),
}

/// The fixture's description of `device`.
pub fn description(device: Device) -> Result<od::DeviceDescription, SmdSlaveError> {
    let select = od::esi::Select::Name(device.order_code().to_string());
    Ok(od::esi::read(
        FIXTURE_ESI.as_bytes(),
        FIXTURE_NAME,
        Some(&select),
    )?)
}

/// A chain of virtual SMD units ([`UnitChain`] of [`SmdUnit`]). A clone is a second chain in the
/// same state (a fuzz target or a test builds one chain from the description and clones it for each
/// case).
pub type SmdChain = UnitChain<SmdUnit>;

impl UnitChain<SmdUnit> {
    /// `n` units of `device`, serial numbers 1…n, all in Init (SMD-T2-007), powered on at `now`, running
    /// their process-data cycle every `cycle` (at least 1 µs).
    pub fn new(
        device: Device,
        n: usize,
        cycle: Duration,
        now: Instant,
    ) -> Result<SmdChain, SmdSlaveError> {
        let desc = description(device)?;
        let ec = desc.ethercat.as_ref().ok_or(SmdSlaveError::NoEthercat)?;
        let at = |kind: &str| {
            ec.sync_managers
                .iter()
                .find(|s| s.kind == kind)
                .map_or(0, |s| s.start_address)
        };
        let (outputs_at, inputs_at) = (at("Outputs"), at("Inputs"));
        let mailbox_in = ec
            .sync_managers
            .iter()
            .find(|s| s.kind == "MBoxIn")
            .and_then(|s| s.default_size)
            .unwrap_or(128);
        let mut units = Vec::new();
        for k in 0..n {
            // The fixture ESI's FMMUs and SyncManagers (3 and 4).
            let mut esc = Esc::for_device(&desc);
            esc.sii = od::sii::write(&desc, k as u32 + 1)?;
            esc.load_sii_configuration();
            esc.al = AlConfig::from_description(&desc);
            esc.al.sync0_cycle = Some(SYNC0_CYCLE_RANGE);
            let mut model = SmdUnit::new(device, EncoderKind::Incremental)?;
            if k == 0 {
                // The layouts of SM2 and SM3 must come from the PDO assignment and mapping.
                ProcessImage::from_assignment(model.dict(), 0x1C12)?;
                ProcessImage::from_assignment(model.dict(), 0x1C13)?;
            }
            model.set_network_state(now, NetworkState::Init);
            model.set_serial_number(k as u32 + 1);
            // One process-data exchange per cycle of the chain (as `from_units` takes it).
            model
                .indexer_mut()
                .start(now, cycle.max(Duration::from_micros(1)));
            let coe = CoeServer::new(ServerConfig::default(), usize::from(mailbox_in));
            units.push((
                esc,
                Unit::new(model, coe, Some(outputs_at), Some(inputs_at)),
            ));
        }
        Ok(UnitChain::from_units(units, cycle, now))
    }
}

/// The indexer as a unit of a chain: SYNC0 is the indexer's DC_Sync event, the SyncManager watchdog
/// its Input_Error, the AL state its network state (PreOp_SafeOp, commands only in Op).
impl Model for SmdUnit {
    fn process_images(&self) -> Result<(ProcessImage, ProcessImage), AlStatusCode> {
        let d = self.dict();
        let outputs = ProcessImage::from_assignment(d, 0x1C12)
            .map_err(|_| AlStatusCode::InvalidOutputMapping)?;
        let inputs = ProcessImage::from_assignment(d, 0x1C13)
            .map_err(|_| AlStatusCode::InvalidInputMapping)?;
        Ok((outputs, inputs))
    }

    fn set_al_state(&mut self, _from: AlState, to: AlState, now: Instant) {
        self.set_network_state(
            now,
            match to {
                AlState::Op => NetworkState::Op,
                AlState::SafeOp => NetworkState::SafeOp,
                AlState::PreOp => NetworkState::PreOp,
                _ => NetworkState::Init,
            },
        );
    }

    fn outputs_lost(&mut self, now: Instant) {
        // SMD-R1-035: the model reports Input_Error and PreOp_SafeOp.
        self.indexer_mut().sm_watchdog_expired(now);
    }

    fn device(&mut self) -> &mut dyn od::hook::Device {
        self.model_mut()
    }

    /// SYNC0 only: the indexer runs its process-data exchange at the unit's cycle, not at a new
    /// output image.
    fn sync(&mut self, at: Instant, event: SyncEvent) {
        if event == SyncEvent::Sync0 {
            self.device().sync(at);
        }
    }
}
