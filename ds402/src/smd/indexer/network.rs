//! The EtherCAT state as the unit sees it (Op or not, the SyncManager watchdog) and DC_Sync's
//! SYNC0 events.

use std::time::{Duration, Instant};

use super::{Indexer, SyncWait};

/// The EtherCAT state machine's state, as far as the unit's behaviour depends on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NetworkState {
    /// Init: no process data.
    Init,
    /// Pre-Operational: mailbox (CoE) only.
    PreOp,
    /// Safe-Operational: inputs are sent, outputs not acted on.
    SafeOp,
    /// Operational: commands are processed.
    #[default]
    Op,
}

/// Delay from SYNC0 to the start of motion with DC_Sync (SMD-R1-022).
pub const SYNC0_START_DELAY: Duration = Duration::from_micros(520);

impl Indexer {
    /// The EtherCAT state changes at `now` (SMD-R6-056, SMD-R6-072, SMD-R6-073), acted on at once:
    /// leaving Op stops a move where the motion stands and makes the position invalid; on entering
    /// Op the first output data to come is the edge reference, a command bit already 1 in it is no
    /// edge.
    pub fn set_network_state(&mut self, _now: Instant, state: NetworkState) {
        if self.network == NetworkState::Op && state != NetworkState::Op {
            if self.busy() {
                self.stop_now();
            }
            self.position_invalid = true;
        }
        if self.network != NetworkState::Op && state == NetworkState::Op {
            // SMD-R6-073: the first output data in Op is the edge reference.
            self.edge_reference_pending = true;
        }
        self.network = state;
    }

    /// The master stopped updating the outputs for longer than the SyncManager watchdog, which
    /// expired at `now`: Input_Error and Safe-Op (SMD-R1-035, SMD-R6-054). A move runs up to `now`
    /// and stops there (SMD-R6-056).
    pub fn sm_watchdog_expired(&mut self, now: Instant) {
        if self.busy() {
            self.run_motion_to(now);
        }
        self.input_error = true;
        self.set_network_state(now, NetworkState::SafeOp);
    }

    /// A SYNC0 event of the Distributed Clock at `now`: with DC_Sync, a move waiting for it starts
    /// 520 µs after `now` (SMD-R1-022). An event reported with an instant before the exchange the
    /// motion last ran to counts from that exchange (the move it starts was taken there).
    pub fn sync0_event(&mut self, now: Instant) {
        if self.sync_wait == Some(SyncWait::ForSync0) {
            let since = self
                .ran_to
                .map_or(Duration::ZERO, |t| now.saturating_duration_since(t));
            self.sync_wait = Some(SyncWait::Delay(SYNC0_START_DELAY + since));
        }
    }

    /// The EtherCAT state.
    pub fn network_state(&self) -> NetworkState {
        self.network
    }
}
