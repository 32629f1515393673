// scratch, to be deleted
use envspec::{load, Override};
#[test]
fn probe() {
    let dir = std::env::var("PROBE_DIR").unwrap_or("/tmp/envspec_docs_probe".into());
    let mut entries: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).filter(|p| p.extension().map_or(false, |e| e == "toml")).collect();
    entries.sort();
    for p in entries {
        let over = p.with_extension("over");
        let ov: Vec<Override> = std::fs::read_to_string(&over).map(|s| s.lines().filter(|l| !l.is_empty()).map(|l| Override::parse(l).unwrap()).collect()).unwrap_or_default();
        println!("########## {}", p.display());
        match std::panic::catch_unwind(|| load(&p, &ov)).unwrap_or_else(|_| { println!("PANIC"); Err(envspec::Diagnostics::default()) }) {
            Ok(r) => println!("OK obs_dim={} reward={:?}", r.obs_dim, r.reward.iter().map(|t| &t.name).collect::<Vec<_>>()),
            Err(e) => { for d in e.iter() { println!("[{:?}] pos={:?} help={:?}", d.code, d.position(), d.help); } println!("{e}"); }
        }
    }
}
