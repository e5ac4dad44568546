//! `flexbody study --report page.html`: one self-contained page with the
//! study's table (the figures `study` prints), every plot inline, the
//! model, version, command line and date; rendered by a real browser
//! (headless Chromium, Debian's `chromium`) without errors, its screenshot
//! showing the table and the plots.

use super::support::{run_ok, skip_without_peer};
use std::path::Path;
use std::process::Command;

#[test]
fn study_report_holds_the_table_and_every_plot_and_renders_in_chromium() {
    let dir = tempfile::tempdir().unwrap();
    let (out, page) = (dir.path().join("plots"), dir.path().join("review.html"));
    let model = super::side_beam_path();
    let o = run_ok(&[
        "study",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--report",
        page.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(&page).unwrap();
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["plots", "review.html"],
        "no temporary left beside the page"
    );

    // The table has the rows `study` prints, cell by cell.
    let printed = String::from_utf8(o.stdout).unwrap();
    let printed_rows: Vec<Vec<&str>> = printed
        .lines()
        .skip_while(|l| !l.starts_with("method"))
        .skip(1)
        .take_while(|l| !l.starts_with("plots:"))
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert_eq!(printed_rows.len(), 7 * 2, "7 cases at 2 Omegas: {printed}");
    assert_eq!(table_rows(&html, "errors"), printed_rows);

    // Every plot `study` wrote is on the page, as the same SVG markup.
    let mut plots = 0;
    for entry in std::fs::read_dir(&out).unwrap() {
        let svg = std::fs::read_to_string(entry.unwrap().path()).unwrap();
        assert!(
            html.contains(svg.trim_end()),
            "a plot missing from the page"
        );
        plots += 1;
    }
    assert_eq!(plots, 16);
    assert_eq!(html.matches("<svg ").count(), plots);

    // Self-contained: no scripts and nothing fetched from elsewhere (the
    // only address is the SVG namespace's name).
    assert!(!html.contains("<script") && !html.contains(" src=") && !html.contains(" href="));
    assert_eq!(
        html.matches("http").count(),
        html.matches("xmlns=\"http://www.w3.org/2000/svg\"").count()
    );
    // What ran, on what, when.
    assert!(html.contains(&format!("<code>{}</code>", env!("CARGO_PKG_VERSION"))));
    assert!(html.contains(&format!("--report {}", page.display())));
    assert!(html.contains(" UTC</code>"));
    // The model as `flexbody info` describes it.
    let info = run_ok(&["info", model.to_str().unwrap()]);
    let info = String::from_utf8(info.stdout).unwrap();
    let after = |prefix: &str| -> String {
        let line = info.lines().find(|l| l.starts_with(prefix)).unwrap();
        line[prefix.len()..].to_string()
    };
    let (nodes, elements) = after("nodes ")
        .split_once(", elements ")
        .map(|(n, e)| (n.to_string(), e.to_string()))
        .unwrap();
    let dofs = after("DOFs ").split(',').next().unwrap().to_string();
    let mass = after("mass along x, y, z (kg), free DOFs: ");
    for (what, value) in [
        ("nodes", nodes),
        ("elements", elements),
        ("DOFs", dofs),
        ("mass along x, y, z (kg)", mass),
    ] {
        let fact = format!("<th>{what}</th><td>{value}</td>");
        assert!(html.contains(&fact), "{fact}");
    }

    let Some(chromium) = chromium() else {
        skip_without_peer(
            "study_report_holds_the_table_and_every_plot_and_renders_in_chromium",
            "chromium",
        );
        return;
    };
    // The page as Chromium built it: the table and the plots are there,
    // and the console reported no error.
    let dom = headless(&chromium, &page, &["--dump-dom"]);
    let console = String::from_utf8_lossy(&dom.stderr);
    for line in console.lines() {
        assert!(
            !(line.contains("CONSOLE") || line.contains("Uncaught")),
            "console: {line}"
        );
    }
    let dom = String::from_utf8_lossy(&dom.stdout);
    assert!(dom.contains(r#"<table class="errors">"#), "{dom:.300}");
    assert_eq!(dom.matches("<svg ").count(), plots);

    // Its screenshot shows the table's grey rules and the plots' curves.
    let png = dir.path().join("page.png");
    let shot = format!("--screenshot={}", png.display());
    headless(&chromium, &page, &[&shot, "--window-size=1200,4000"]);
    let image = Rgb::decode(&png);
    let table_rules = (0..image.height)
        .filter(|&y| {
            (0..image.width)
                .filter(|&x| image.near(x, y, [0xbb, 0xbb, 0xbb]))
                .count()
                > 300
        })
        .count();
    assert!(table_rules >= 10, "{table_rules} rows of table rules");
    // The convergence plots' first curve (#0072b2), and the reduced curves
    // of the case plots (#d55e00).
    for colour in [[0x00, 0x72, 0xb2], [0xd5, 0x5e, 0x00]] {
        let pixels = (0..image.height)
            .flat_map(|y| (0..image.width).map(move |x| (x, y)))
            .filter(|&(x, y)| image.near(x, y, colour))
            .count();
        assert!(pixels > 500, "{pixels} pixels of {colour:?}");
    }
}

/// The `<td>` texts of each row of `table.<class>`.
fn table_rows<'a>(html: &'a str, class: &str) -> Vec<Vec<&'a str>> {
    let start = html
        .find(&format!(r#"<table class="{class}">"#))
        .expect("the table");
    let table = &html[start..start + html[start..].find("</table>").unwrap()];
    table
        .split("<tr>")
        .filter(|row| row.contains("<td>"))
        .map(|row| {
            row.split("<td>")
                .skip(1)
                .map(|cell| &cell[..cell.find("</td>").unwrap()])
                .collect()
        })
        .collect()
}

/// Debian's `chromium`, if installed.
fn chromium() -> Option<String> {
    let ok = Command::new("chromium")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then(|| "chromium".to_string())
}

/// Runs headless Chromium on `page` with `args`, expecting success.
fn headless(chromium: &str, page: &Path, args: &[&str]) -> std::process::Output {
    let profile = tempfile::tempdir().unwrap();
    let o = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(args)
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("run chromium");
    assert!(
        o.status.success(),
        "chromium: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

/// A decoded RGB(A) image.
struct Rgb {
    width: usize,
    height: usize,
    channels: usize,
    pixels: Vec<u8>,
}

impl Rgb {
    fn decode(path: &Path) -> Rgb {
        let decoder = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(path).expect("the screenshot"),
        ));
        let mut reader = decoder.read_info().unwrap();
        let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut pixels).unwrap();
        assert_eq!(info.bit_depth, png::BitDepth::Eight);
        let channels = match info.color_type {
            png::ColorType::Rgb => 3,
            png::ColorType::Rgba => 4,
            other => panic!("screenshot in {other:?}"),
        };
        pixels.truncate(info.buffer_size());
        Rgb {
            width: info.width as usize,
            height: info.height as usize,
            channels,
            pixels,
        }
    }

    /// Whether pixel `(x, y)` is within 24 of `colour` in each channel.
    fn near(&self, x: usize, y: usize, colour: [u8; 3]) -> bool {
        let at = (y * self.width + x) * self.channels;
        (0..3).all(|c| self.pixels[at + c].abs_diff(colour[c]) <= 24)
    }
}
