//! Random parts of descriptions for the write → read properties of the EDS and XDD formats.

use od::device::CanInfo;
use od::value::TimeValue;
use od::{AccessType, DataType, Value};
use proptest::prelude::*;
use proptest::sample::{select, subsequence};

/// Any access type.
pub fn access() -> impl Strategy<Value = AccessType> {
    select(vec![
        AccessType::Ro,
        AccessType::Wo,
        AccessType::Rw,
        AccessType::Rwr,
        AccessType::Rww,
        AccessType::Const,
    ])
}

/// A value of type `t`. Strings are made by `text`, which holds what the format can carry.
pub fn value(t: DataType, text: impl Strategy<Value = String> + 'static) -> BoxedStrategy<Value> {
    match t {
        DataType::Boolean => any::<bool>().prop_map(Value::Bool).boxed(),
        DataType::Real32 => prop_oneof![Just(0.0f32), proptest::num::f32::NORMAL]
            .prop_map(Value::Real32)
            .boxed(),
        DataType::Real64 => prop_oneof![Just(0.0f64), proptest::num::f64::NORMAL]
            .prop_map(Value::Real64)
            .boxed(),
        DataType::VisibleString => text.prop_map(Value::String).boxed(),
        DataType::UnicodeString => text
            .prop_map(|s| Value::Unicode(s.encode_utf16().collect()))
            .boxed(),
        DataType::OctetString | DataType::Domain => proptest::collection::vec(any::<u8>(), 0..8)
            .prop_map(Value::Bytes)
            .boxed(),
        DataType::TimeOfDay | DataType::TimeDifference => (0..=0x0FFF_FFFFu32, any::<u16>())
            .prop_map(|(ms, days)| Value::Time(TimeValue { ms, days }))
            .boxed(),
        t => {
            let (lo, hi) = t.integer_range().unwrap();
            if t.is_signed() {
                (lo as i64..=hi as i64).prop_map(Value::Int).boxed()
            } else {
                (0..=hi as u64).prop_map(Value::Uint).boxed()
            }
        }
    }
}

/// CAN parts with bit rates from `baud_rates` and a granularity from `granularity`; the flags and counts
/// are anything, the dummy types some of Dummy0001 to Dummy0007 (all that the XDD schema knows).
pub fn can_info(
    baud_rates: impl Strategy<Value = Vec<u32>>,
    granularity: impl Strategy<Value = u8>,
) -> impl Strategy<Value = CanInfo> {
    (
        baud_rates,
        any::<[bool; 4]>(),
        (granularity, any::<u8>(), any::<u16>(), any::<u16>()),
        subsequence((1u16..=7).collect::<Vec<_>>(), 0..=7),
    )
        .prop_map(
            |(baud_rates, flags, (granularity, dynamic, rx, tx), dummy_usage)| CanInfo {
                baud_rates,
                simple_boot_up_master: flags[0],
                simple_boot_up_slave: flags[1],
                granularity,
                dynamic_channels: dynamic,
                group_messaging: flags[2],
                nr_of_rx_pdo: rx,
                nr_of_tx_pdo: tx,
                lss_supported: flags[3],
                dummy_usage,
            },
        )
}
