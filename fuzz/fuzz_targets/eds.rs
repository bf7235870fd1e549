//! The CiA 306 EDS/DCF reader on arbitrary bytes: it must answer `Ok` or `Err`, never panic, and what
//! it reads must survive the writers.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(desc) = od::eds::read(data, "fuzz") {
        let eds = od::eds::write_eds(&desc);
        let _ = od::eds::read(eds.as_bytes(), "fuzz-eds");
        let dcf = od::eds::write_dcf(&desc);
        let _ = od::eds::read(dcf.as_bytes(), "fuzz-dcf");
    }
});
