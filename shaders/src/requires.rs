//! The `// requires:` directive and the composition order it fixes, over file paths and texts
//! alone. The build script compiles this same file (`#[path]`) to check every embedded file's
//! requirements before the crate builds, and the library uses it to order a kernel's files,
//! so the rule is written once.

/// The directive naming the files a WGSL file needs, in its leading comment lines.
pub const REQUIRES_DIRECTIVE: &str = "// requires:";

/// The paths `source`'s `// requires:` directives name, in the order written. Only the
/// leading comment lines are read: a directive after the first line of code is not one.
pub fn requires(source: &str) -> impl Iterator<Item = &str> {
    source
        .lines()
        .map(str::trim_start)
        .take_while(|line| line.starts_with("//"))
        .filter_map(|line| line.strip_prefix(REQUIRES_DIRECTIVE))
        .flat_map(str::split_whitespace)
}

/// The composition order of the file at `root` (whose text is `source_of(root)`): the files
/// its directives name, transitively, depth first in the order written, each once, after
/// everything it requires; `root` last. Errs on a path `source_of` has no text for, or on a
/// cycle, naming the chain.
pub fn order<'a>(
    root: &'a str,
    source_of: &dyn Fn(&str) -> Option<(&'a str, &'a str)>,
) -> Result<Vec<&'a str>, String> {
    let source = source_of(root)
        .map(|(_, source)| source)
        .ok_or_else(|| format!("no WGSL file {root} under shaders/"))?;
    let mut out = Vec::new();
    visit(root, source, source_of, &mut Vec::new(), &mut out)?;
    Ok(out)
}

/// Depth-first post-order over the directives: `path`'s requirements in the order written,
/// then `path`, skipping paths already listed. `chain` is the path being followed.
fn visit<'a>(
    path: &'a str,
    source: &'a str,
    source_of: &dyn Fn(&str) -> Option<(&'a str, &'a str)>,
    chain: &mut Vec<&'a str>,
    out: &mut Vec<&'a str>,
) -> Result<(), String> {
    if out.contains(&path) {
        return Ok(());
    }
    if chain.contains(&path) {
        return Err(format!("requires cycle: {} -> {path}", chain.join(" -> ")));
    }
    chain.push(path);
    for needed in requires(source) {
        let (needed, needed_source) = source_of(needed)
            .ok_or_else(|| format!("{path} requires {needed}, which is no file under shaders/"))?;
        visit(needed, needed_source, source_of, chain, out)?;
    }
    chain.pop();
    out.push(path);
    Ok(())
}
