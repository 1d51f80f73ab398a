//! The error of CPCA-compressed glossy transfer against the uncompressed
//! matrices, over the clusters `C` and the basis vectors per cluster `K`,
//! on the bundled meshes: a markdown table per mesh of the RMS error of the
//! matrix entries relative to their RMS, and the bytes stored.
//!
//! `cargo run --release -p shlight-prt --example cpca_curve [-- DIR]`
//!
//! With `DIR`, also a log-log plot per mesh, `DIR/cpca-MESH.svg`: the error
//! against the KiB stored, a line per `K` through the cluster counts.
//!
//! The bake: `shlight prt MESH --mode glossy --brdf phong:32 --lmax 4
//! --samples 512` (shadowed, grey); docs/shprt.md shows the tables.

use std::path::{Path, PathBuf};

use shlight_accuracy::plot::{Series, log_log_svg, write_svg};

use shlight_prt::{BakeRequest, Brdf, Mode, bake_glossy_file, compress_file};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let plots = std::env::args_os().nth(1).map(PathBuf::from);
    let request = BakeRequest {
        lmax: 4,
        samples: 512,
        mode: Mode::Shadowed,
        albedo: None,
        seed: 0,
    };
    let clusters = [1usize, 4, 16, 64, 256];
    let vectors = [0usize, 1, 2, 4, 8, 16];
    for name in ["bunny.obj", "teapot.obj"] {
        let path = root.join("meshes").join(name);
        let mesh = shlight_mesh::load(&path).expect("a bundled mesh");
        let (_, file) = bake_glossy_file(
            &mesh,
            None,
            &path,
            &request,
            Brdf::Phong { exponent: 32.0 },
            &|_, _, _| {},
        );
        let before = 4 * file.transfer.len();
        println!(
            "{name} ({} vertices; uncompressed {:.2} MiB): RMS error / RMS entry, and MiB stored\n",
            mesh.vertex_count(),
            before as f64 / f64::from(1u32 << 20)
        );
        print!("| C \\ K |");
        for k in vectors {
            print!(" {k} |");
        }
        println!();
        println!("|---|{}", "---|".repeat(vectors.len()));
        let mut series: Vec<Series> = vectors
            .iter()
            .map(|k| Series {
                label: format!("K = {k}"),
                points: Vec::new(),
                dashed: false,
            })
            .collect();
        for c in clusters {
            print!("| {c} |");
            for (k, line) in vectors.into_iter().zip(&mut series) {
                let mut f = file.clone();
                let e = compress_file(&mut f, c, k, 0).expect("compresses");
                line.points
                    .push((e.bytes_after as f64 / 1024.0, e.rms / e.rms_entries));
                print!(
                    " {:.1}% ({:.2}) |",
                    100.0 * e.rms / e.rms_entries,
                    e.bytes_after as f64 / f64::from(1u32 << 20)
                );
            }
            println!();
        }
        println!();
        if let Some(dir) = &plots {
            let stem = name.trim_end_matches(".obj");
            let svg = log_log_svg(
                &format!(
                    "{name}: CPCA of glossy transfer (lmax 4), C = {clusters:?} along each line"
                ),
                "KiB stored",
                "RMS error / RMS entry",
                &series,
            )
            .expect("a plot");
            let path = dir.join(format!("cpca-{stem}.svg"));
            write_svg(&path, &svg).expect("the plot written");
            println!("wrote {}\n", path.display());
        }
    }
}
