use super::*;

fn count(svg: &str, tag: &str) -> usize {
    svg.matches(&format!("<{tag} ")).count()
}

/// The `points` of every `<polyline>` that is not black (the axes and ticks are), parsed.
fn polylines(svg: &str) -> Vec<Vec<(f64, f64)>> {
    svg.split("<polyline ")
        .skip(1)
        .filter(|p| !p[..p.find("/>").expect("closed")].contains("stroke=\"#000000\""))
        .map(|p| {
            let a = p.find("points=\"").expect("points") + 8;
            let b = a + p[a..].find('"').expect("closing quote");
            p[a..b]
                .split_whitespace()
                .map(|xy| {
                    let (x, y) = xy.split_once(',').expect("x,y");
                    (x.parse().expect("x"), y.parse().expect("y"))
                })
                .collect()
        })
        .collect()
}

/// The text of every `<text>` element (plotters puts it on a line of its own).
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text ")
        .skip(1)
        .map(|t| {
            let a = t.find('>').expect("tag end") + 1;
            let b = t.find("</text>").expect("closing tag");
            t[a..b].trim().to_string()
        })
        .collect()
}

fn has_text(svg: &str, text: &str) -> bool {
    texts(svg).iter().any(|t| t == text)
}

fn valid(svg: &str) {
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
    assert!(svg.trim_end().ends_with("</svg>"));
}

#[test]
fn a_known_series_gives_one_polyline_of_its_points_with_title_and_labels() {
    let x = vec![0.0, 1.0, 2.0, 3.0, 4.0];
    let y = vec![0.0, 2.0, -1.0, 3.0, 0.5];
    let svg = lines(
        "midspan Z <test>",
        "t (s)",
        "midspan_z (mm)",
        &[Series::new("fe", x, y)],
    )
    .unwrap();
    valid(&svg);
    let p = polylines(&svg);
    assert_eq!(p.len(), 2, "the curve and its legend swatch");
    assert_eq!(p[0].len(), 5);
    assert_eq!(p[1].len(), 2);
    // Pixel y grows downwards: the highest value (3 at x = 3) is the topmost point.
    let top = p[0].iter().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    assert_eq!(*top, p[0][3]);
    for text in ["midspan Z &lt;test&gt;", "t (s)", "midspan_z (mm)", "fe"] {
        assert!(has_text(&svg, text), "{text} missing");
    }
}

#[test]
fn degenerate_series_give_valid_svgs() {
    let flat = Series::new("flat", (0..1000).map(f64::from).collect(), vec![0.01; 1000]);
    let zero = Series::new("zero", vec![0.0, 1.0], vec![0.0, 0.0]);
    let one = Series::new("one", vec![2.0], vec![5.0]);
    let empty = Series::new("empty", vec![], vec![]);
    let nan = Series::new("nan", vec![0.0, 1.0], vec![f64::NAN, f64::NAN]);
    let inf = Series::new("inf", vec![0.0, f64::INFINITY], vec![1.0, 2.0]);
    for s in [&flat, &zero, &one, &empty, &nan, &inf] {
        let svg = lines("t", "x", "y", std::slice::from_ref(s)).unwrap();
        valid(&svg);
        assert!(has_text(&svg, &s.label), "{}", s.label);
    }
    // The flat history is drawn as a horizontal line through all its points.
    let p = polylines(&lines("t", "x", "y", &[flat]).unwrap())[0].clone();
    assert_eq!(p.len(), 1000);
    assert!(p.iter().all(|q| q.1 == p[0].1));
    // No series at all.
    valid(&lines("nothing", "x", "y", &[]).unwrap());
}

#[test]
fn non_finite_values_break_the_curve() {
    let s = Series::new(
        "gappy",
        vec![0.0, 1.0, 2.0, 3.0, 4.0],
        vec![1.0, 2.0, f64::NAN, 3.0, 4.0],
    );
    let p = polylines(&lines("t", "x", "y", &[s]).unwrap());
    assert_eq!(p.len(), 3, "two stretches and the swatch");
    assert_eq!((p[0].len(), p[1].len()), (2, 2));
}

/// Draws `plot` alone and returns its layout and SVG.
fn layout(plot: &Plot) -> (Layout, String) {
    let mut s = String::new();
    let l = {
        let root = SVGBackend::with_string(&mut s, (WIDTH, HEIGHT)).into_drawing_area();
        let l = draw(&root, plot, TITLE_PX).unwrap();
        root.present().unwrap();
        l
    };
    (l, s)
}

#[test]
fn the_legend_box_lies_right_of_the_data_area_and_holds_its_text() {
    let t: Vec<f64> = (0..500).map(|k| k as f64 * 1e-3).collect();
    // A peak at the top right corner, where an inset legend would sit.
    let y = |a: f64| t.iter().map(|&x| a * x * x).collect::<Vec<_>>();
    let label = "a rather long label, Δt = 0.0001 s";
    let plot = Plot::new(
        "legend",
        "t (s)",
        "z (mm)",
        vec![
            Series::new("modal", t.clone(), y(1.0)),
            Series::new(label, t.clone(), y(2.0)),
        ],
    );
    let (l, svg) = layout(&plot);
    let (px0, py0, px1, py1) = l.plotting;
    let (lx0, ly0, lx1, ly1) = l.legend.unwrap();
    assert!(px0 < px1 && py0 < py1);
    assert!(
        lx0 >= px1,
        "legend {lx0} starts left of the data area's right edge {px1}"
    );
    assert!(lx1 <= WIDTH as i32 && ly0 >= 0 && ly1 <= HEIGHT as i32);
    // The drawn box is the one in the layout.
    let rect = format!(
        "<rect x=\"{lx0}\" y=\"{ly0}\" width=\"{}\" height=\"{}\"",
        lx1 - lx0,
        ly1 - ly0
    );
    assert!(svg.contains(&rect), "{rect} not in the SVG");
    // The label starts inside the box and its estimated width ends inside it.
    let at = svg.find(&format!("\n{label}\n")).unwrap();
    let open = svg[..at].rfind("<text ").unwrap();
    let x: i32 = svg[open..]
        .split("x=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(x > lx0);
    assert!(x as f64 + text_width(label, LABEL_PX) < lx1 as f64);
    // Every curve point lies in the data area (plotters clips to it).
    for p in polylines(&svg).iter().take(2) {
        assert!(p.iter().all(|&(x, _)| x as i32 >= px0 && x as i32 <= px1));
    }
}

#[test]
fn the_width_estimate_covers_dejavu_sans() {
    // DejaVu Sans advances (units per em 2048) of the widest glyphs in our labels: digits
    // 1303, 'e' 1260, 'Δ' 1403, ' ' 651, 'm' 1995, 'W' 2025.
    let em = |units: f64| units / 2048.0;
    let label = "FE, Δt = 0.0001 s";
    let approx: f64 = label
        .chars()
        .map(|c| match c {
            '0'..='9' => em(1303.0),
            ' ' => em(651.0),
            'Δ' => em(1403.0),
            ',' | '.' => em(651.0),
            '=' => em(1716.0),
            'E' => em(1294.0),
            'F' => em(1178.0),
            't' => em(803.0),
            's' => em(1067.0),
            _ => 1.0,
        })
        .sum();
    assert!(
        text_width(label, 1.0) >= approx,
        "{} < {approx}",
        text_width(label, 1.0)
    );
}

#[test]
fn a_zero_line_is_drawn_and_kept_in_range() {
    let s = Series::new("gap", vec![0.0, 1.0], vec![2.0, 3.0]);
    let plot = Plot::new("gap", "t (s)", "gap − h0 (mm)", vec![s]).zero_line();
    let (l, svg) = layout(&plot);
    let p = polylines(&svg);
    assert_eq!(p.len(), 3, "zero line, curve, swatch");
    let zero = &p[0];
    assert_eq!(zero.len(), 2);
    assert_eq!(zero[0].1, zero[1].1, "horizontal");
    assert!((zero[0].1 as i32) > l.plotting.1 && (zero[0].1 as i32) < l.plotting.3);
    // Below the curve (y = 0 < 2).
    assert!(p[1].iter().all(|q| q.1 < zero[0].1));
}

#[test]
fn long_series_are_thinned_per_pixel_column_keeping_the_peaks() {
    let n = 200_000;
    let x: Vec<f64> = (0..n).map(|k| k as f64).collect();
    let mut y: Vec<f64> = x.iter().map(|&v| (v * 1e-3).sin()).collect();
    y[123_457] = 5.0;
    y[4_321] = -7.0;
    let pts: Vec<(f64, f64)> = x.iter().copied().zip(y.iter().copied()).collect();
    let t = thin(&pts, 0.0, (n - 1) as f64, 500);
    assert!(t.len() <= 4 * 501, "{}", t.len());
    assert!(t.contains(&(123_457.0, 5.0)) && t.contains(&(4_321.0, -7.0)));
    assert_eq!(t.first(), pts.first());
    assert_eq!(t.last(), pts.last());
    assert!(t.windows(2).all(|w| w[0].0 < w[1].0), "in order");
    // Through the SVG: the spike is the topmost point of the drawn curve.
    let svg = lines("spike", "x", "y", &[Series::new("s", x, y)]).unwrap();
    let p = &polylines(&svg)[0];
    assert!(p.len() <= 4 * WIDTH as usize);
    let top = p.iter().map(|q| q.1).fold(f64::INFINITY, f64::min);
    let bottom = p.iter().map(|q| q.1).fold(f64::NEG_INFINITY, f64::max);
    assert!(top < bottom);
}

#[test]
fn panels_are_one_svg_with_every_title() {
    let s = |a: f64| vec![Series::new("modal", vec![0.0, 1.0], vec![0.0, a])];
    let plots: Vec<Plot> = ["A", "B", "C", "D"]
        .iter()
        .enumerate()
        .map(|(i, t)| Plot::new(format!("panel {t}"), "t (s)", "z (mm)", s(i as f64 + 1.0)))
        .collect();
    let svg = panels("figure [--set seed=2]", 2, &plots).unwrap();
    valid(&svg);
    assert_eq!(count(&svg, "svg"), 1, "not nested");
    assert!(svg.contains(&format!("width=\"{}\"", 2 * WIDTH)));
    for t in [
        "figure [--set seed=2]",
        "panel A",
        "panel B",
        "panel C",
        "panel D",
    ] {
        assert!(has_text(&svg, t), "{t}");
    }
    assert_eq!(polylines(&svg).len(), 8, "a curve and a swatch per panel");
    assert!(panels("x", 0, &plots).is_err());
}

#[test]
fn long_titles_wrap_within_the_width() {
    let title = "§4.3 midspan Z at 100 m/s [--set irregularity.seed=2, controller.alpha=0.4, geometry=paper, vehicle.magnet_mass_kg=400]";
    let lines = wrap(title, WIDTH as f64 - 20.0, TITLE_PX);
    assert!(lines.len() >= 2);
    assert_eq!(lines.join(" "), title);
    assert!(lines
        .iter()
        .all(|l| text_width(l, TITLE_PX) <= WIDTH as f64 - 20.0));
    let svg = lines_svg(title);
    for l in &lines {
        assert!(has_text(&svg, l), "{l}");
    }
}

fn lines_svg(title: &str) -> String {
    super::lines(
        title,
        "x",
        "y",
        &[Series::new("s", vec![0.0, 1.0], vec![0.0, 1.0])],
    )
    .unwrap()
}

#[test]
fn tick_labels() {
    assert_eq!(tick_label(0.0, 2.0, 1.0), "0");
    assert_eq!(tick_label(1.0, 4.4, 3.0), "1");
    assert_eq!(tick_label(-0.5, 4.4, 3.0), "-0.5");
    assert_eq!(tick_label(1e-12, 2.0, 1.0), "0");
    assert_eq!(tick_label(0.25, 0.4, 1.0), "0.25");
    assert_eq!(tick_label(12.0, 40.0, 40.0), "12");
    assert_eq!(tick_label(-0.002, 0.01, 0.005), "-0.002");
    assert_eq!(tick_label(36790.0, 1e5, 1e5), "3.68e4");
    assert_eq!(tick_label(2e-5, 1e-4, 1e-4), "2.00e-5");
}

/// A logarithmic x axis: the points 0.5 … 200 are placed by log10 (equal ratios, equal
/// distances), the ticks are 0.5, 1, 2, 5, …, 200 labelled in the data's units, and x ≤ 0
/// breaks the curve.
#[test]
fn a_log_x_axis_places_points_by_log10_with_1_2_5_ticks() {
    let x = vec![0.5, 5.0, 50.0, 200.0];
    let y = vec![1.0, 2.0, 3.0, 4.0];
    let svg =
        svg(&Plot::new("log", "f (Hz)", "L (dB)", vec![Series::new("a", x, y)]).log_x()).unwrap();
    let p = &polylines(&svg)[0];
    assert_eq!(p.len(), 4);
    let (d1, d2) = (p[1].0 - p[0].0, p[2].0 - p[1].0);
    assert!((d1 - d2).abs() <= 1.0, "{d1} vs {d2}");
    for tick in ["0.5", "1", "2", "5", "10", "20", "50", "100", "200"] {
        assert!(has_text(&svg, tick), "tick {tick}");
    }
    assert!(!has_text(&svg, "0.7") && !has_text(&svg, "-0.3"));
    let broken = svg_of_log(vec![1.0, 0.0, 10.0, 100.0]);
    assert_eq!(
        polylines(&broken).len(),
        1 + 2,
        "two stretches and the legend swatch"
    );
}

fn svg_of_log(x: Vec<f64>) -> String {
    let y = vec![1.0; x.len()];
    svg(&Plot::new("t", "x", "y", vec![Series::new("a", x, y)]).log_x()).unwrap()
}

/// Markers: one per point of every series (circles for the first, squares for the others)
/// and one per legend entry; none without `markers()`.
#[test]
fn markers_are_drawn_at_every_point() {
    let series = vec![
        Series::new("a", vec![0.0, 1.0, 2.0], vec![1.0, 2.0, 3.0]),
        Series::new("b", vec![0.0, 1.0, 2.0], vec![1.0, 2.0, 3.0]),
    ];
    let plain = svg(&Plot::new("m", "x", "y", series.clone())).unwrap();
    assert_eq!(count(&plain, "circle"), 0);
    let marked = svg(&Plot::new("m", "x", "y", series).markers()).unwrap();
    assert_eq!(count(&marked, "circle"), 3 + 1);
    let squares = marked
        .split("<rect ")
        .skip(1)
        .filter(|r| r[..r.find("/>").expect("closed")].contains("stroke=\"#D62728\""))
        .count();
    assert_eq!(squares, 3 + 1);
}
