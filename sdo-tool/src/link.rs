//! What the tool takes from the crates that reach the networks: the CAN side (`socketcan-node`:
//! frames, buses, the node's constants) and the EtherCAT side (`ethercat-slave`: the raw socket).
//! The rest of the tool names these through this module only.

pub use ethercat_slave::raw::RawSocket;
pub use socketcan_node::node::pdo::{PdoConfig, RPDO_COMM, TPDO_COMM};
pub use socketcan_node::node::{EmcyCode, LOAD_SIGNATURE, SAVE_SIGNATURE};
pub use socketcan_node::transport::open as open_spec;
pub use socketcan_node::transport::{
    BusError, BusEvent, BusSpec, CanBus, SocketCanBus, SocketcandClient, BUS_VARIABLE,
    SOCKETCAND_DEFAULT_PORT,
};
pub use socketcan_node::CanFrame;
