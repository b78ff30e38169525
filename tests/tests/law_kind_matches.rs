//! No code outside `core/src/law/` matches on the law's kind (`maglev_core::LawKind`): what
//! callers need to know of a law (its supply bound, control period, sensors, whether it
//! batches, its parameters' names in errors) they ask the law (`maglev_core::law`), so a new
//! law is added in the core alone. Building a law (`LawKind::State(gains)`) is fine; a
//! pattern on it (`match` arms, `matches!`, `if let`, or-patterns) is not.

use std::path::{Path, PathBuf};

/// Whether `line` holds a pattern on `LawKind` (not a construction of one).
fn is_pattern(line: &str) -> bool {
    let code = line.split("//").next().unwrap_or("");
    let mut rest = code;
    let mut offset = 0;
    while let Some(i) = rest.find("LawKind::") {
        let at = offset + i;
        let (before, after) = code.split_at(at);
        let head = before.trim_start();
        // The variant and its parenthesised fields, then what follows them.
        let tail = after.trim_start_matches("LawKind::");
        let name_end = tail
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(tail.len());
        let mut follow = &tail[name_end..];
        if follow.starts_with('(') {
            let mut depth = 0;
            let mut end = follow.len();
            for (k, c) in follow.char_indices() {
                match c {
                    '(' => depth += 1,
                    ')' => {
                        depth -= 1;
                        if depth == 0 {
                            end = k + 1;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            let fields = &follow[..end];
            if fields == "(_)" || fields.contains("..") {
                return true;
            }
            follow = &follow[end..];
        }
        let follow = follow.trim_start_matches(')').trim_start();
        if follow.starts_with("=>")
            || follow.starts_with('|')
            || follow.starts_with("if ")
            || before.contains("matches!(")
            || ((head.starts_with("if let") || head.starts_with("while let"))
                && follow.starts_with('='))
            || (head.starts_with("let ") && after.contains("else"))
        {
            return true;
        }
        offset = at + "LawKind::".len();
        rest = &code[offset..];
    }
    false
}

/// Every `.rs` file under `dir`, build outputs left out.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name();
        if p.is_dir() {
            if name != "target" && name != ".git" {
                sources(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn the_detector_tells_patterns_from_constructions() {
    for pattern in [
        "        LawKind::State(s) => dt / s.periods(dt) as f64,",
        "        LawKind::Paper | LawKind::GapLoop(_) => controller.v_max,",
        "    accel: matches!(s.law, maglev_core::LawKind::State(_)).then(|| Accels {",
        "    if let LawChoice::Given(LawKind::State(s)) | LawChoice::DesignState(s) = law {",
        "            LawChoice::Given(LawKind::State(_)) | LawChoice::DesignState(_)",
        "    let LawKind::State(s) = law else {",
        "        Some(LawKind::GapLoop(g)) if g.kp > 0.0 => 1,",
        "        LawKind::GapLoop(GapParams { kp, .. }) => kp,",
    ] {
        assert!(is_pattern(pattern), "{pattern}");
    }
    for construction in [
        "            MAGLEV_LAW_PAPER => LawKind::Paper,",
        "    let state = LawKind::State(state_law::gains());",
        "        return Ok(LawChoice::Given(LawKind::Paper));",
        "                LawKind::GapLoop(GapParams {",
        "            _ => LawKind::GapLoop(stable_gap_loop(",
        "        law: maglev_core::LawKind::Paper, // LawKind::Paper => x",
        "        for kind in [LawKind::Paper, LawKind::GapLoop(GapParams::designed())] {",
        "pub fn voltage_bound(law: &LawKind) -> Option<f64> {",
        "    let s = settings(SPEED, 1.0, LawKind::Paper, Geometry::Paper, vec![]);",
    ] {
        assert!(!is_pattern(construction), "{construction}");
    }
}

#[test]
fn nothing_outside_the_core_law_matches_the_law_kind() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in [
        "core",
        "host-sim",
        "firmware-sim",
        "c-api",
        "tests",
        "python",
    ] {
        sources(&root.join(dir), &mut files);
    }
    let law_dir = root.join("core/src/law");
    let this = Path::new(file!()).file_name().unwrap();
    let mut found = Vec::new();
    for f in &files {
        if f.starts_with(&law_dir) || f.file_name() == Some(this) {
            continue;
        }
        let text = std::fs::read_to_string(f).unwrap();
        for (k, line) in text.lines().enumerate() {
            if is_pattern(line) {
                let rel = f.strip_prefix(&root).unwrap_or(f);
                found.push(format!("{}:{}: {}", rel.display(), k + 1, line.trim()));
            }
        }
    }
    assert!(files.len() > 100, "only {} sources found", files.len());
    assert!(
        found.is_empty(),
        "matches on LawKind outside core/src/law/ (ask the law instead, maglev_core::law):\n{}",
        found.join("\n")
    );
}
