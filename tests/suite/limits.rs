//! The memory budget knows the limit the process runs under: under an address-space cap
//! (`prlimit --as`, what many batch systems set) a job is refused with the one-line budget
//! message before it starts, its image before it is decoded, instead of aborting on a failed
//! allocation halfway; and the budget falls as the cap falls.

use std::process::Command;

/// The caps tried, MiB, from the largest down.
const CAPS_MIB: [u64; 5] = [1536, 1024, 768, 512, 256];

/// The budget a refusal names ("the budget is 812 MB"), in bytes.
fn budget_named(stderr: &str) -> Option<u64> {
    let rest = stderr.split("the budget is ").nth(1)?;
    let mut words = rest.split_whitespace();
    let value: f64 = words.next()?.parse().ok()?;
    let unit = words.next()?.trim_end_matches([':', ',']);
    let scale = match unit {
        "GB" => 1e9,
        "MB" => 1e6,
        _ => return None,
    };
    Some((value * scale) as u64)
}

#[test]
fn under_every_cap_a_4096_px_scene_gives_a_result_or_one_line_and_the_budget_falls_with_the_cap() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("scene.hdr");
    // 4096 × 4096, the largest scene: its decode holds about 670 MB, the grey sensor run 870 MB.
    const SIDE: u32 = 4096;
    let img = image::Rgb32FImage::from_fn(SIDE, SIDE, |x, y| {
        let v = 0.05 + (x as f32 / SIDE as f32) * (y as f32 / SIDE as f32);
        image::Rgb([v, v, v])
    });
    image::DynamicImage::ImageRgb32F(img)
        .save(&path)
        .expect("write the scene");
    let mut budgets: Vec<(u64, u64)> = Vec::new();
    let mut results = 0usize;
    for cap_mib in CAPS_MIB {
        let cap = cap_mib << 20;
        let out = Command::new("prlimit")
            .arg(format!("--as={cap}"))
            .arg("--")
            .arg(env!("CARGO_BIN_EXE_udc-studio"))
            .args(["sensor", "--json", "--hdr"])
            .arg(&path)
            .output()
            .expect("prlimit (util-linux) runs the binary");
        let stderr = String::from_utf8_lossy(&out.stderr);
        match out.status.code() {
            Some(0) => {
                let v: serde_json::Value =
                    serde_json::from_slice(&out.stdout).expect("the run's JSON");
                assert_eq!(v["strategies"].as_array().map(Vec::len), Some(4), "{v}");
                results += 1;
            }
            Some(1) => {
                assert_eq!(stderr.trim().lines().count(), 1, "{cap_mib} MiB: {stderr}");
                assert!(stderr.contains("needs about"), "{cap_mib} MiB: {stderr}");
                let budget = budget_named(&stderr)
                    .unwrap_or_else(|| panic!("{cap_mib} MiB: no budget in {stderr}"));
                assert!(budget < cap, "{cap_mib} MiB: budget {budget}");
                if cap_mib <= 512 {
                    // Refused from the header, before a pixel is decoded.
                    assert!(
                        stderr.contains("decoding the 4096×4096 HDR image"),
                        "{stderr}"
                    );
                }
                budgets.push((cap_mib, budget));
            }
            other => panic!("{cap_mib} MiB: exit {other:?} (an abort?): {stderr}"),
        }
    }
    // The smallest caps cannot even decode the scene; they refuse before decoding.
    assert!(budgets.len() >= 3, "{budgets:?}");
    for pair in budgets.windows(2) {
        assert!(
            pair[1].1 <= pair[0].1,
            "the budget rose as the cap fell: {budgets:?}"
        );
    }
    println!("{results} results; budgets by cap (MiB, bytes): {budgets:?}");
}
