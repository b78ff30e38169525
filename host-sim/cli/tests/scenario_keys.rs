//! docs/scenarios.md against the code: every section and key the scenario reader knows is in
//! the page's tables, and the page lists nothing the reader does not know; "required" there
//! agrees with the reader; every accepted word of an enum key is named in its row; the short
//! `--set` keys are `scenario::SHORT_KEYS`; the page's from-scratch example is the shipped
//! file, loads, and runs.
//!
//! The key lists come from the code, not from this file: every section struct has
//! `deny_unknown_fields` (`[bridge]` and `[bridge.pier]`, read by `scenario::WithSection`,
//! refuse a key the same way), so a section holding the key `zz_unknown` is refused with
//! serde's "unknown field `zz_unknown`, expected one of `a`, `b`, …". A section tagged by `kind` is
//! refused without its tag ("missing field `kind`") and with `kind = "zz_unknown"` lists its
//! kinds ("unknown variant"); each kind then lists its own keys. A key is a sub-table when
//! `[section.key]` holding `zz_unknown` is refused the same way.

use maglev_sim::input::case::Case;
use maglev_sim::input::scenario::{self, BUNDLED, SHORT_KEYS};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

const DOC: &str = include_str!("../../../docs/scenarios.md");
const EXAMPLE: &str = include_str!("../../sim/scenarios/examples/from-scratch.toml");

fn example_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../sim/scenarios/examples/from-scratch.toml")
}

/// One table of keys as the code reads it: a section (`[]` the top level), and the value of
/// its tag for a tagged section.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Section {
    path: Vec<String>,
    kind: Option<String>,
}

impl Section {
    fn name(&self) -> String {
        let mut n = format!("[{}]", self.path.join("."));
        if let Some(k) = &self.kind {
            n += &format!(" kind = {k:?}");
        }
        n
    }
}

/// What the code knows of one section: its keys (the tag included), which of them are
/// sub-tables, and the tag's name for a tagged section.
#[derive(Debug, Default)]
struct Keys {
    keys: BTreeSet<String>,
    tables: BTreeSet<String>,
    tag: Option<String>,
}

/// The reader's error for scenario text `text` ("" when it reads).
fn error(text: &str) -> String {
    match scenario::parse(text, "scenario_keys", &[]) {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    }
}

/// Scenario text holding only section `path` (with `tag = "kind"` when given) and `line`.
fn text(path: &[String], tag: Option<(&str, &str)>, line: &str) -> String {
    let mut t = String::new();
    if !path.is_empty() {
        t += &format!("[{}]\n", path.join("."));
    }
    if let Some((tag, kind)) = tag {
        t += &format!("{tag} = {kind:?}\n");
    }
    t + line + "\n"
}

/// The names serde lists after "unknown {what} `zz_unknown`, expected": `a`, `a` or `b`,
/// one of `a`, `b`, ….
fn expected(msg: &str, what: &str) -> Option<Vec<String>> {
    let marker = format!("unknown {what} `zz_unknown`, expected ");
    let rest = &msg[msg.find(&marker)? + marker.len()..];
    let list = rest.split(" in `").next().unwrap_or(rest);
    Some(
        list.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect(),
    )
}

/// The field serde names in "missing field `X`".
fn missing(msg: &str) -> Option<String> {
    let rest = &msg[msg.find("missing field `")? + "missing field `".len()..];
    Some(rest.split('`').next()?.to_string())
}

fn is_table(path: &[String]) -> bool {
    let msg = error(&text(path, None, "zz_unknown = 1"));
    expected(&msg, "field").is_some() || missing(&msg).is_some()
}

/// Every section the reader knows, from section `path` down.
fn discover(path: Vec<String>, out: &mut BTreeMap<Section, Keys>) {
    let msg = error(&text(&path, None, "zz_unknown = 1"));
    let mut found = Vec::new();
    if let Some(keys) = expected(&msg, "field") {
        found.push((None, keys, None));
    } else if let Some(tag) = missing(&msg) {
        let msg = error(&text(&path, None, &format!("{tag} = \"zz_unknown\"")));
        let kinds = expected(&msg, "variant")
            .unwrap_or_else(|| panic!("[{}]: no kinds in: {msg}", path.join(".")));
        for kind in kinds {
            let msg = error(&text(&path, Some((&tag, &kind)), "zz_unknown = 1"));
            let keys = expected(&msg, "field")
                .unwrap_or_else(|| panic!("[{}] {kind}: no keys in: {msg}", path.join(".")));
            found.push((Some(kind), keys, Some(tag.clone())));
        }
    } else {
        panic!(
            "[{}]: neither keys nor a tag in the reader's error: {msg}",
            path.join(".")
        );
    }
    for (kind, list, tag) in found {
        let mut k = Keys {
            tag: tag.clone(),
            ..Keys::default()
        };
        for key in list {
            let sub = [path.clone(), vec![key.clone()]].concat();
            // Sub-tables of a tagged section's kinds are not reached by this walk; none exist.
            if kind.is_none() && is_table(&sub) {
                k.tables.insert(key.clone());
                discover(sub, out);
            }
            k.keys.insert(key);
        }
        k.keys.extend(tag);
        assert!(!k.keys.is_empty(), "[{}]: no keys", path.join("."));
        out.insert(
            Section {
                path: path.clone(),
                kind,
            },
            k,
        );
    }
}

fn code_sections() -> BTreeMap<Section, Keys> {
    let mut out = BTreeMap::new();
    discover(Vec::new(), &mut out);
    out
}

/// A `### ` table of docs/scenarios.md: its heading and its rows' cells (header and
/// separator rows dropped).
struct DocTable {
    heading: String,
    rows: Vec<Vec<String>>,
}

fn doc_tables() -> Vec<DocTable> {
    let mut tables: Vec<DocTable> = Vec::new();
    let mut open = false;
    for line in DOC.lines() {
        if let Some(h) = line.strip_prefix("### ") {
            tables.push(DocTable {
                heading: h.trim().to_string(),
                rows: Vec::new(),
            });
            open = true;
        } else if line.starts_with("## ") || line.starts_with("# ") {
            open = false;
        } else if open && line.starts_with('|') {
            let t = tables.last_mut().unwrap();
            let cells = split_row(line);
            t.rows.push(cells);
        }
    }
    for t in &mut tables {
        // The header row and the |---| row.
        assert!(t.rows.len() >= 2, "### {}: no table", t.heading);
        assert!(t.rows[1].iter().all(|c| c.chars().all(|ch| ch == '-')));
        t.rows.drain(..2);
    }
    tables
}

/// The cells of a markdown row; `|` inside backticks stays in its cell.
fn split_row(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    let (mut cells, mut cell, mut code) = (Vec::new(), String::new(), false);
    for ch in inner.chars() {
        match ch {
            '`' => {
                code = !code;
                cell.push(ch);
            }
            '|' if !code => cells.push(std::mem::take(&mut cell).trim().to_string()),
            _ => cell.push(ch),
        }
    }
    cells.push(cell.trim().to_string());
    cells
}

/// A row's key: its first cell without backticks (and without the brackets of `[section]`).
fn row_key(row: &[String]) -> String {
    row[0]
        .trim_matches('`')
        .trim_start_matches('[')
        .trim_end_matches(']')
        .to_string()
}

/// The sections a key table's heading covers: every `[path]` in it, with its `kind = "…"`.
fn heading_sections(heading: &str) -> Vec<Section> {
    let kind = heading
        .split_once("kind = \"")
        .map(|(_, r)| r.split('"').next().unwrap().to_string());
    let mut out = Vec::new();
    let mut rest = heading;
    while let Some(i) = rest.find('[') {
        let j = rest[i..].find(']').expect("unclosed [") + i;
        out.push(Section {
            path: rest[i + 1..j].split('.').map(str::to_string).collect(),
            kind: kind.clone(),
        });
        rest = &rest[j + 1..];
    }
    out
}

/// The page's key tables by section: "Sections" is the top level.
fn doc_sections() -> BTreeMap<Section, Vec<Vec<String>>> {
    let mut out = BTreeMap::new();
    for t in doc_tables() {
        let sections = if t.heading == "Sections" {
            vec![Section {
                path: Vec::new(),
                kind: None,
            }]
        } else {
            heading_sections(&t.heading)
        };
        for s in sections {
            let name = s.name();
            assert!(
                out.insert(s, t.rows.clone()).is_none(),
                "{name} has two tables"
            );
        }
    }
    out
}

/// Every key of every section and kind is in the page's table for it, and every table's keys
/// are the code's.
#[test]
fn every_key_is_documented_and_no_other() {
    let code = code_sections();
    // The walk found what a scenario has: the top level, the sub-tables, the kinds.
    for must in [
        "[]",
        "[run]",
        "[soil]",
        "[vehicle] kind = \"fig1\"",
        "[train] kind = \"wheel-rail\"",
        "[controller]",
    ] {
        assert!(
            code.keys().any(|s| s.name() == must),
            "the walk missed {must}: {:?}",
            code.keys().map(Section::name).collect::<Vec<_>>()
        );
    }
    let doc = doc_sections();
    let mut problems = Vec::new();
    for (s, k) in &code {
        let Some(rows) = doc.get(s) else {
            problems.push(format!("{}: no table in docs/scenarios.md", s.name()));
            continue;
        };
        let documented: BTreeSet<String> = rows.iter().map(|r| row_key(r)).collect();
        for key in k.keys.difference(&documented) {
            problems.push(format!("{}: key `{key}` is not documented", s.name()));
        }
        for key in documented.difference(&k.keys) {
            problems.push(format!(
                "{}: the page documents `{key}`, which the code does not know",
                s.name()
            ));
        }
        for r in rows {
            if r.len() != 7 || r.iter().any(|c| c.is_empty()) {
                problems.push(format!(
                    "{}: row `{}` needs 7 filled cells (key, unit, type, default, accepted, meaning, relates to)",
                    s.name(),
                    row_key(r)
                ));
            }
        }
    }
    for s in doc.keys() {
        if !code.contains_key(s) {
            problems.push(format!(
                "{}: the page has a table for a section the code does not know",
                s.name()
            ));
        }
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

/// A key is "required" on the page exactly when the reader refuses a scenario without it:
/// each key of each bundled scenario (and of the example) is left out in turn.
#[test]
fn required_on_the_page_is_required_by_the_code() {
    let code = code_sections();
    let doc = doc_sections();
    let mut samples: Vec<(String, String)> = BUNDLED
        .iter()
        .map(|(n, t)| (n.to_string(), t.to_string()))
        .collect();
    samples.push(("from-scratch".into(), EXAMPLE.into()));
    // The bridge's damping, a sub-table no bundled file has.
    samples.push((
        "moving-force, damped".into(),
        BUNDLED
            .iter()
            .find(|(n, _)| *n == "moving-force")
            .unwrap()
            .1
            .to_string()
            + "\n[bridge.damping]\nratio = 0.02\nf1_Hz = 6.0\nf2_Hz = 30.0\n",
    ));
    // The state law's gains, the one sub-table no file has.
    samples.push((
        "from-scratch, state law".into(),
        EXAMPLE.replace("law = \"gap-loop\"", "law = \"state\"")
            + "\n[controller.state]\nkp_V_per_m = 12900.0\nkd_V_s_per_m = 1900.0\n\
               ka_V_s2_per_m = 0.0\nki_V_per_m_s = 2150.0\nkc_V_per_A = 1.0\nvmax_V = 300.0\n\
               rate_Hz = 10000.0\nobserver_Hz = 300.0\n",
    ));
    // The guidance law's gains, on paper-4.2's guided car under the state law.
    let p42 = BUNDLED.iter().find(|(n, _)| *n == "paper-4.2").unwrap().1;
    samples.push((
        "paper-4.2, guided".into(),
        p42.replace("vmax_V = inf", "vmax_V = inf\nlaw = \"state\"")
            + "\n[controller.state]\nkp_V_per_m = 51600.0\nkd_V_s_per_m = 1600.0\n\
               ka_V_s2_per_m = 40.0\nki_V_per_m_s = 4300.0\nkc_V_per_A = 10.0\nvmax_V = 500.0\n\
               \n[controller.guidance]\nkp_V_per_m = 51600.0\nkd_V_s_per_m = 1600.0\n\
               ka_V_s2_per_m = 0.0\nki_V_per_m_s = 4300.0\nkc_V_per_A = 10.0\n",
    ));
    // paper-5's train as the one kind no file has: its [train] holds `cars` only.
    let p5 = BUNDLED.iter().find(|(n, _)| *n == "paper-5").unwrap().1;
    samples.push((
        "paper-5 wheel-rail".into(),
        p5.replace("kind = \"maglev\"", "kind = \"wheel-rail\""),
    ));
    // Ground receivers, which no bundled file asks for.
    samples.push((
        "paper-5 with receivers".into(),
        p5.to_string() + "\n[ground]\ndistances_m = [12.5, 25.0]\npier = 20\n",
    ));
    let mut required: BTreeMap<Section, BTreeSet<String>> = BTreeMap::new();
    let mut seen: BTreeSet<Section> = BTreeSet::new();
    for (name, t) in &samples {
        let table: toml::Table = toml::from_str(t).unwrap();
        for (s, k) in &code {
            if s.path.is_empty() {
                continue;
            }
            // The section under the name the sample gives it ([vehicle] and [train] are one).
            let mut path = s.path.clone();
            let alias = match path[0].as_str() {
                "vehicle" => "train",
                "train" => "vehicle",
                _ => "",
            };
            if !table.contains_key(&path[0]) && table.contains_key(alias) {
                path[0] = alias.to_string();
            }
            let Some(sec) = lookup(&table, &path) else {
                continue;
            };
            if let (Some(kind), Some(tag)) = (&s.kind, &k.tag) {
                if sec.get(tag).and_then(|v| v.as_str()) != Some(kind) {
                    continue;
                }
            }
            seen.insert(s.clone());
            for key in sec.keys() {
                let mut t = table.clone();
                lookup_mut(&mut t, &mut path).unwrap().remove(key);
                let msg = error(&toml::to_string(&t).unwrap());
                if missing(&msg).as_deref() == Some(key) {
                    required.entry(s.clone()).or_default().insert(key.clone());
                } else {
                    assert!(
                        msg.is_empty() || !msg.contains("missing field"),
                        "{name} without {}.{key}: {msg}",
                        s.name()
                    );
                }
            }
        }
    }
    let mut problems = Vec::new();
    for (s, k) in &code {
        if s.path.is_empty() {
            continue;
        }
        if !seen.contains(s) {
            problems.push(format!("{}: no sample scenario has it", s.name()));
            continue;
        }
        let Some(rows) = doc.get(s) else { continue };
        for r in rows {
            let key = row_key(r);
            let says = r.get(3).is_some_and(|c| c.starts_with("required"));
            let is = required.get(s).is_some_and(|r| r.contains(&key));
            if says != is && k.keys.contains(&key) {
                problems.push(format!(
                    "{}: `{key}` is {}required in the code, the page's default says `{}`",
                    s.name(),
                    if is { "" } else { "not " },
                    r.get(3).map_or("", |c| c.as_str())
                ));
            }
        }
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

fn lookup<'a>(t: &'a toml::Table, path: &[String]) -> Option<&'a toml::Table> {
    path.iter().try_fold(t, |t, p| t.get(p)?.as_table())
}

fn lookup_mut<'a>(t: &'a mut toml::Table, path: &mut [String]) -> Option<&'a mut toml::Table> {
    path.iter().try_fold(t, |t, p| t.get_mut(p)?.as_table_mut())
}

/// Every word an enum key accepts (serde's "unknown variant … expected …") is named, in
/// backticks, in the key's row.
#[test]
fn every_accepted_word_is_named() {
    let doc = doc_sections();
    let mut problems = Vec::new();
    let mut enums = 0;
    for (s, k) in &code_sections() {
        let Some(rows) = doc.get(s) else { continue };
        for key in k.keys.difference(&k.tables) {
            if Some(key) == k.tag.as_ref() {
                continue; // the kinds are the tables themselves
            }
            let tag = k.tag.as_deref().zip(s.kind.as_deref());
            let msg = error(&text(&s.path, tag, &format!("{key} = \"zz_unknown\"")));
            let Some(words) = expected(&msg, "variant") else {
                continue;
            };
            enums += 1;
            let row = rows.iter().find(|r| row_key(r) == *key);
            for w in words {
                if !row.is_some_and(|r| r.join("|").contains(&format!("`{w}`"))) {
                    problems.push(format!("{}: `{key}` accepts `{w}`, not named", s.name()));
                }
            }
        }
    }
    // model, bridge.kind, two geometry, interp, law, scheme.
    assert!(enums >= 7, "only {enums} enum keys found");
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));
}

/// The page's short-key table is `scenario::SHORT_KEYS`, and each stands for a key the code
/// knows.
#[test]
fn short_keys_are_the_codes() {
    let tables = doc_tables();
    let t = tables
        .iter()
        .find(|t| t.heading == "Short `--set` keys")
        .expect("a ### Short `--set` keys table");
    let doc: BTreeSet<(String, String)> = t
        .rows
        .iter()
        .map(|r| (row_key(r), r[1].trim_matches('`').to_string()))
        .collect();
    let code: BTreeSet<(String, String)> = SHORT_KEYS
        .iter()
        .map(|(s, f)| (s.to_string(), f.to_string()))
        .collect();
    assert_eq!(doc, code);
    let sections = code_sections();
    for (short, full) in SHORT_KEYS {
        let (section, key) = full.split_once('.').unwrap();
        assert!(
            sections
                .iter()
                .any(|(s, k)| s.path == [section] && k.keys.contains(key)),
            "{short} stands for {full}, which the code does not know"
        );
    }
}

/// The example on the page is the shipped file, it loads, and it runs under `--strict` with
/// the step count the page states.
#[test]
fn the_from_scratch_example_runs() {
    assert!(
        DOC.contains(&format!("```toml\n{EXAMPLE}```")),
        "docs/scenarios.md must show host-sim/sim/scenarios/examples/from-scratch.toml verbatim"
    );
    let path = example_path();
    let case = Case::load(path.to_str().unwrap(), &[]).unwrap();
    assert!((case.t_end - 0.85).abs() < 1e-12, "{}", case.t_end);
    let out = std::env::temp_dir().join(format!("maglev-scenario-keys-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = Command::new(env!("CARGO_BIN_EXE_maglev"))
        .args(["run", path.to_str().unwrap(), "--strict", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("850 steps"), "{err}");
    let csv = std::fs::read_to_string(out.join("response.csv")).unwrap();
    assert_eq!(
        csv.lines().next().unwrap(),
        "t,span1.midspan.z,wheel1.gap_z,wheel1.force_z,car1.body.az,iterations,collision"
    );
    std::fs::remove_dir_all(&out).unwrap();
}
