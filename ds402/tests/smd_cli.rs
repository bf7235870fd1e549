//! The `smd` binary as a user runs it.

mod smd_bin;

use smd_bin::smd;

/// The arguments of `smd profile` for Table R3.2's values and a 300,000-step move.
const TABLE_R3_2: [&str; 11] = [
    "profile",
    "--start",
    "141",
    "--speed",
    "100000",
    "--accel",
    "20",
    "--decel",
    "25",
    "--distance",
    "300000",
];

/// `smd profile` with the Table R3.2 values and a 300,000-step move (SMD-R3-009, SMD-R3-011).
#[test]
fn profile_prints_the_phases_and_the_peak() {
    let (code, out, err) = smd(&TABLE_R3_2);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(
        lines[1],
        "profile       triangular, below the programmed speed (D_A + D_D at the programmed speed = 449999.1 steps)"
    );
    assert_eq!(
        lines[2],
        "acceleration  linear                   4.0754 s       166666.7 steps  141.0 -> 81649.8 steps/s"
    );
    assert_eq!(
        lines[5],
        "deceleration  linear                   3.2604 s       133333.3 steps  81649.8 -> 141.0 steps/s"
    );
    assert_eq!(
        lines[7],
        "total                                  7.3358 s       300000.0 steps  peak 81649.8 steps/s"
    );
}

/// `--jerk 400` with Example 2's values (SMD-R3-018) and `--plot`: a real SVG chart with its axes.
#[test]
fn profile_s_curve_and_its_chart() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("profile.svg");
    let (code, out, err) = smd(&[
        "profile",
        "--start",
        "1",
        "--speed",
        "30001",
        "--accel",
        "58",
        "--decel",
        "58",
        "--jerk",
        "400",
        "--distance",
        "-100000",
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("trapezoidal S-curve      0.7672 s"), "{out}");
    assert!(
        out.contains(
            "t1 = 0.2500 s, S1 = 7250.0 steps/s, t2 = 0.1336 s, 34.8 % at a = 58000 steps/s²"
        ),
        "{out}"
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"), "{}", &text[..80.min(text.len())]);
    for label in ["time [s]", "speed [steps/s]", "jerk 400", "30000"] {
        assert!(text.contains(label), "the chart has no {label:?}");
    }
    assert!(text.contains("<polyline"), "no curve in the chart");
}

#[test]
fn bad_profile_arguments_exit_2_with_the_reason() {
    let (code, _, err) = smd(&[
        "profile",
        "--speed",
        "100",
        "--accel",
        "20",
        "--decel",
        "25",
        "--distance",
        "5",
    ]);
    assert_eq!(code, 2);
    assert_eq!(
        err.trim(),
        "smd: programmed speed 100 steps/s is below the starting speed 141 steps/s"
    );
    let (code, _, err) = smd(&[
        "profile",
        "--speed",
        "1000",
        "--accel",
        "0",
        "--decel",
        "25",
        "--distance",
        "5",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("acceleration 0 is outside 1 to 5000"), "{err}");
    let (code, _, err) = smd(&[
        "profile",
        "--start",
        "0",
        "--speed",
        "1000",
        "--accel",
        "1",
        "--decel",
        "1",
        "--distance",
        "5",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("0 is not in 1..=1999999"), "{err}");
}

/// `smd config encode` is the table R5.3 calculator (SMD-R5-016, SMD-R5-011 with the encoder).
#[test]
fn config_encode_prints_the_word() {
    let (code, out, err) = smd(&[
        "config",
        "encode",
        "--input1",
        "cw-limit",
        "--input2",
        "ccw-limit",
        "--encoder",
        "--stall-detection",
    ]);
    assert_eq!((code, out.as_str()), (0, "0x2411\n"), "{err}");
    let (code, out, _) = smd(&[
        "config",
        "encode",
        "--input1",
        "home",
        "--in1-active-on-current",
        "--dc-sync",
    ]);
    assert_eq!((code, out.as_str()), (0, "0x0006\n0x0041\n"));
}

/// An invalid combination is printed with the rule it breaks, and the exit code is 1 (SMD-R5-018,
/// SMD-R5-011).
#[test]
fn config_encode_names_the_broken_rules() {
    let (code, out, _) = smd(&[
        "config",
        "encode",
        "--input1",
        "home",
        "--input2",
        "home",
        "--stall-detection",
    ]);
    assert_eq!(code, 1);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "0x2036");
    assert!(
        lines[1].starts_with("invalid: invalid configuration 3 (same function on both inputs)"),
        "{out}"
    );
    assert!(lines[1].ends_with("[SMD-R5-018]"), "{out}");
    assert!(
        lines[2].starts_with("invalid: invalid configuration 4 (stall detection without encoder)"),
        "{out}"
    );
    let (code, _, err) = smd(&["config", "encode", "--input1", "sideways"]);
    assert_eq!(code, 2);
    assert!(err.contains("unknown input function \"sideways\""), "{err}");
}

/// `smd config decode` names the settings both ways and the broken rules (SMD-R5-012, SMD-R5-017,
/// SMD-R5-025).
#[test]
fn config_decode_names_settings_and_violations() {
    let (code, out, _) = smd(&["config", "decode", "0x2411", "3"]);
    assert_eq!(code, 0);
    for line in [
        "CFG_Word_0 = 0x2411",
        "Input 1: CW Limit",
        "Input 2: CCW Limit",
        "Use_Encoder: yes",
        "Enable_Stall_Detection: yes",
        "CFG_Word_1 = 0x0003",
        "Valid: yes",
    ] {
        assert!(out.lines().any(|l| l == line), "no line {line:?} in\n{out}");
    }
    let (code, out, _) = smd(&["config", "decode", "0x1007", "0b100"]);
    assert_eq!(code, 1);
    assert!(out.contains("Valid: no"), "{out}");
    for rule in ["[SMD-R5-012]", "[SMD-R5-017]", "[SMD-R5-025]"] {
        assert!(out.contains(rule), "{rule} missing:\n{out}");
    }
    let (code, _, err) = smd(&["config", "decode", "0x10000"]);
    assert_eq!(code, 2);
    assert!(err.contains("is not a 16-bit word"), "{err}");
}

/// `--json`: each command's result is one JSON object with numbers as numbers, and nothing else on
/// standard output; an error is a JSON object too (exit 2).
#[test]
fn json_output_of_every_command() {
    let parse = |out: &str| -> Vec<serde_json::Value> {
        out.lines()
            .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l:?}: {e}")))
            .collect()
    };
    // The profile of Table R3.2's values (SMD-R3-009, SMD-R3-011): the same figures as the text.
    let mut argv = vec!["--json"];
    argv.extend(TABLE_R3_2);
    let (code, out, err) = smd(&argv);
    assert_eq!(code, 0, "{err}");
    let v = parse(&out);
    assert_eq!(v.len(), 1, "{out}");
    let p = &v[0];
    assert_eq!(p["shape"], "triangular");
    assert_eq!(
        format!("{:.1}", p["peak_speed"].as_f64().unwrap()),
        "81649.8"
    );
    assert_eq!(
        format!("{:.4}", p["total_time"].as_f64().unwrap()),
        "7.3358"
    );
    assert_eq!(
        format!("{:.1}", p["total_distance"].as_f64().unwrap()),
        "300000.0"
    );
    assert_eq!(
        format!("{:.4}", p["accel"]["time"].as_f64().unwrap()),
        "4.0754"
    );
    assert_eq!(p["accel"]["shape"], "linear");
    assert_eq!(p["accel"]["low_speed"], 141.0);
    assert_eq!(
        format!("{:.1}", p["decel"]["distance"].as_f64().unwrap()),
        "133333.3"
    );
    assert_eq!(p["cruise"]["distance"], 0.0);

    // 0x2411 (SMD-R5-001): Input 1 CW Limit, Input 2 CCW Limit, encoder, stall detection.
    let (code, out, _) = smd(&[
        "--json",
        "config",
        "encode",
        "--input1",
        "cw-limit",
        "--input2",
        "ccw-limit",
        "--encoder",
        "--stall-detection",
    ]);
    assert_eq!(code, 0);
    let v = parse(&out);
    assert_eq!(v.len(), 1);
    assert_eq!(v[0]["cfg_word0"], 0x2411);
    assert_eq!(v[0]["cfg_word1"], serde_json::Value::Null);
    assert_eq!(v[0]["cfg0"]["input1"], "CW Limit");
    assert_eq!(v[0]["cfg0"]["input2"], "CCW Limit");
    assert_eq!(v[0]["cfg0"]["use_encoder"], true);
    assert_eq!(v[0]["valid"], true);
    assert_eq!(v[0]["violations"], serde_json::json!([]));
    // Any one CFG_Word_1 flag gives CFG_Word_1 (bit 0, bit 1, bit 6: Table R5.3).
    for (flag, word1) in [
        ("--in1-active-on-current", 0x0001),
        ("--in2-active-on-current", 0x0002),
        ("--dc-sync", 0x0040),
    ] {
        let (code, out, _) = smd(&["--json", "config", "encode", flag]);
        assert_eq!(code, 0, "{flag}");
        assert_eq!(parse(&out)[0]["cfg_word1"], word1, "{flag}");
    }
    // Both inputs Home and stall detection without encoder (SMD-R5-018, SMD-R5-011): exit 1.
    let (code, out, _) = smd(&["config", "decode", "0x2036", "0x0041", "--json"]);
    assert_eq!(code, 1);
    let v = parse(&out);
    assert_eq!(v.len(), 1);
    assert_eq!(v[0]["cfg_word0"], 0x2036);
    assert_eq!(v[0]["cfg1"]["in1_active_level"], 1);
    assert_eq!(v[0]["cfg1"]["in2_active_level"], 0);
    assert_eq!(v[0]["cfg1"]["dc_sync"], true);
    assert_eq!(v[0]["valid"], false);
    let rules: Vec<&str> = v[0]["violations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x["rule"].as_str().unwrap())
        .collect();
    assert_eq!(rules, ["SMD-R5-018", "SMD-R5-011"]);

    // A simulation: one object per table line. A Relative move of 5000 steps from a preset 0.
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("relative.smd");
    std::fs::write(
        &script,
        "at 0ms out cmd1=0x8000 velocity=10000 acceleration=100 deceleration=100\n\
         at 10ms out cmd0=0x0200\nat 20ms out cmd0=0\n\
         at 30ms out cmd0=0x0002 position=5000\nat 40ms out cmd0=0\nuntil 1s\n",
    )
    .unwrap();
    let path = script.to_str().unwrap();
    let (code, text, _) = smd(&["simulate", path]);
    assert_eq!(code, 0);
    let (code, out, err) = smd(&["--json", "simulate", path]);
    assert_eq!(code, 0, "{err}");
    let rows = parse(&out);
    // The text's lines less its two header lines.
    assert_eq!(rows.len(), text.lines().count() - 2);
    assert_eq!(rows[0]["t"], 0.0);
    assert_eq!(rows[0]["status_word0"], 0x4408);
    assert_eq!(
        rows[0]["status_word0_bits"],
        serde_json::json!(["Stopped", "Position_Invalid", "Module_OK"])
    );
    let last = rows.last().unwrap();
    assert_eq!(last["t"], 1.0);
    assert_eq!(last["motor_position"], 5000);
    assert_eq!(last["speed"], 0.0);
    assert_eq!(last["status_word0"], 0x4088);
    assert_eq!(
        last["status_word0_bits"],
        serde_json::json!(["Stopped", "Move_Complete", "Module_OK"])
    );
    assert_eq!(
        last["status_word1_bits"],
        serde_json::json!(["Drive_Is_Enabled"])
    );

    // An error: one JSON object on standard output, nothing on standard error.
    let missing = dir.path().join("missing.smd");
    let (code, out, err) = smd(&["--json", "simulate", missing.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert_eq!(err, "");
    let v = parse(&out);
    assert_eq!(v.len(), 1);
    assert_eq!(v[0]["exit_code"], 2);
    assert!(
        v[0]["error"]
            .as_str()
            .unwrap()
            .starts_with(&format!("cannot read {}: ", missing.display())),
        "{out}"
    );
}
