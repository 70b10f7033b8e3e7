//! The public API, listed: every path a user of the crate can name with default features
//! (items, fields, variants, inherent methods, trait impls), read from `src/` with `syn`
//! by following `pub mod` and `pub use` from `lib.rs`. The listing is committed in
//! `public-api.txt`, so the API changes only on purpose: after a deliberate change, run
//! `cargo test -p dualspectra --test public_api -- --ignored bless_public_api` and commit
//! the new file. Items under a `#[cfg(...)]` (tests, features such as `lab`) are not listed.

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::path::{Path, PathBuf};
use syn::{ImplItem, Item, UseTree, Visibility};

/// A module of the crate: its items, read from its file or inline body.
struct Module {
    items: Vec<Item>,
    /// Child modules by name (any visibility).
    children: BTreeMap<String, usize>,
    parent: Option<usize>,
}

struct Crate {
    modules: Vec<Module>,
}

fn enabled(attrs: &[syn::Attribute]) -> bool {
    !attrs.iter().any(|a| a.path().is_ident("cfg"))
}

fn is_pub(vis: &Visibility) -> bool {
    matches!(vis, Visibility::Public(_))
}

impl Crate {
    fn read(lib: &Path) -> Crate {
        let mut krate = Crate { modules: Vec::new() };
        let text = std::fs::read_to_string(lib).unwrap();
        let file = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", lib.display()));
        krate.add(file.items, lib.parent().unwrap().to_path_buf(), None);
        krate
    }

    /// Add a module whose child files live in `dir`; returns its index.
    fn add(&mut self, items: Vec<Item>, dir: PathBuf, parent: Option<usize>) -> usize {
        let id = self.modules.len();
        self.modules.push(Module { items: Vec::new(), children: BTreeMap::new(), parent });
        let mut kept = Vec::new();
        for item in items {
            if let Item::Mod(m) = &item {
                if !enabled(&m.attrs) {
                    continue;
                }
                let name = m.ident.to_string();
                let child = match &m.content {
                    Some((_, inner)) => self.add(inner.clone(), dir.join(&name), Some(id)),
                    None => {
                        let (flat, nested) = (dir.join(format!("{name}.rs")), dir.join(&name).join("mod.rs"));
                        let path = if flat.exists() { flat } else { nested };
                        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                        let file = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                        self.add(file.items, dir.join(&name), Some(id))
                    }
                };
                self.modules[id].children.insert(name, child);
            }
            kept.push(item);
        }
        self.modules[id].items = kept;
        id
    }

    /// What `name` means in module `m`: a child module, an item, or an import to follow.
    fn lookup(&self, m: usize, name: &str, depth: usize) -> Target {
        assert!(depth < 64, "use cycle at {name}");
        if let Some(&c) = self.modules[m].children.get(name) {
            return Target::Module(c);
        }
        for item in &self.modules[m].items {
            if item_name(item).as_deref() == Some(name) && enabled(item_attrs(item)) {
                return Target::Item(m, Box::new(item.clone()));
            }
        }
        for item in &self.modules[m].items {
            if let Item::Use(u) = item {
                if !enabled(&u.attrs) {
                    continue;
                }
                for (path, alias) in leaves(&u.tree, Vec::new()) {
                    if alias.as_deref() == Some(name) {
                        return self.resolve(m, &path, depth + 1);
                    }
                }
            }
        }
        Target::External
    }

    /// Resolve a `use` path seen in module `m`.
    fn resolve(&self, m: usize, path: &[String], depth: usize) -> Target {
        let mut at = m;
        let mut rest = path;
        match path.first().map(String::as_str) {
            Some("crate") => {
                at = 0;
                rest = &path[1..];
            }
            Some("self") => rest = &path[1..],
            _ => {}
        }
        while rest.first().map(String::as_str) == Some("super") {
            at = self.modules[at].parent.expect("super above the crate");
            rest = &rest[1..];
        }
        let mut target = Target::Module(at);
        for seg in rest {
            target = match target {
                Target::Module(c) => self.lookup(c, seg, depth + 1),
                _ => return Target::External,
            };
        }
        target
    }

    /// Inherent pub methods and trait impls of the type named `name` defined in module `def`.
    fn impls_of(&self, def: usize, name: &str) -> (Vec<String>, Vec<String>) {
        let (mut methods, mut traits) = (Vec::new(), Vec::new());
        for (mi, module) in self.modules.iter().enumerate() {
            for item in &module.items {
                let Item::Impl(imp) = item else { continue };
                if !enabled(&imp.attrs) {
                    continue;
                }
                let syn::Type::Path(tp) = &*imp.self_ty else { continue };
                let segs: Vec<String> = tp.path.segments.iter().map(|s| s.ident.to_string()).collect();
                let same = match self.resolve(mi, &segs, 0) {
                    Target::Item(d, it) => d == def && item_name(&it).as_deref() == Some(name),
                    _ => false,
                };
                if !same {
                    continue;
                }
                match &imp.trait_ {
                    Some((_, path, _)) => {
                        let t = path.segments.last().unwrap().ident.to_string();
                        traits.push(t);
                    }
                    None => {
                        for ii in &imp.items {
                            match ii {
                                ImplItem::Fn(f) if is_pub(&f.vis) && enabled(&f.attrs) => methods.push(format!("fn {}", f.sig.ident)),
                                ImplItem::Const(c) if is_pub(&c.vis) && enabled(&c.attrs) => methods.push(format!("const {}", c.ident)),
                                _ => {}
                            }
                        }
                    }
                }
            }
        }
        (methods, traits)
    }

    /// List what module `m` makes public under the external path `at`.
    fn list(&self, m: usize, at: &str, out: &mut BTreeSet<String>, seen: &mut HashSet<(usize, String)>) {
        if !seen.insert((m, at.to_string())) {
            return;
        }
        for item in &self.modules[m].items {
            if !enabled(item_attrs(item)) {
                continue;
            }
            match item {
                Item::Use(u) if is_pub(&u.vis) => {
                    for (path, alias) in leaves(&u.tree, Vec::new()) {
                        match alias {
                            None => {
                                // A glob: everything public in the target module.
                                if let Target::Module(c) = self.resolve(m, &path, 0) {
                                    self.list_public_names(c, m, at, out, seen);
                                }
                            }
                            Some(name) => self.emit(self.resolve(m, &path, 0), &join(at, &name), out, seen),
                        }
                    }
                }
                Item::Mod(md) if is_pub(&md.vis) => {
                    let c = self.modules[m].children[&md.ident.to_string()];
                    self.emit(Target::Module(c), &join(at, &md.ident.to_string()), out, seen);
                }
                _ => {
                    if let (Some(name), Some(vis)) = (item_name(item), item_vis(item)) {
                        if is_pub(vis) {
                            self.emit(Target::Item(m, Box::new(item.clone())), &join(at, &name), out, seen);
                        }
                    }
                }
            }
        }
    }

    /// A glob re-export of module `c` into module `into`: `c`'s public names.
    fn list_public_names(&self, c: usize, _into: usize, at: &str, out: &mut BTreeSet<String>, seen: &mut HashSet<(usize, String)>) {
        self.list(c, at, out, seen);
    }

    fn emit(&self, target: Target, path: &str, out: &mut BTreeSet<String>, seen: &mut HashSet<(usize, String)>) {
        match target {
            Target::Module(c) => {
                out.insert(format!("mod {path}"));
                self.list(c, path, out, seen);
            }
            Target::External => {
                out.insert(format!("use {path} (another crate)"));
            }
            Target::Item(def, item) => {
                let item = *item;
                out.insert(format!("{} {path}", kind(&item)));
                match &item {
                    Item::Struct(s) => {
                        for (i, f) in s.fields.iter().enumerate() {
                            if is_pub(&f.vis) {
                                let name = f.ident.as_ref().map_or(i.to_string(), ToString::to_string);
                                out.insert(format!("field {path}.{name}"));
                            }
                        }
                    }
                    Item::Enum(e) => {
                        for v in &e.variants {
                            out.insert(format!("variant {path}::{}", v.ident));
                        }
                    }
                    Item::Trait(t) => {
                        for ti in &t.items {
                            if let syn::TraitItem::Fn(f) = ti {
                                out.insert(format!("fn {path}::{}", f.sig.ident));
                            }
                        }
                    }
                    _ => {}
                }
                if matches!(item, Item::Struct(_) | Item::Enum(_) | Item::Union(_)) {
                    let name = item_name(&item).unwrap();
                    let (methods, traits) = self.impls_of(def, &name);
                    for m in methods {
                        let (k, n) = m.split_once(' ').unwrap();
                        out.insert(format!("{k} {path}::{n}"));
                    }
                    for t in traits {
                        out.insert(format!("impl {t} for {path}"));
                    }
                }
            }
        }
    }
}

#[derive(Clone)]
enum Target {
    Module(usize),
    Item(usize, Box<Item>),
    External,
}

fn join(at: &str, name: &str) -> String {
    format!("{at}::{name}")
}

/// The leaves of a use tree: (full path, Some(bound name)) or (module path, None) for a glob.
fn leaves(tree: &UseTree, prefix: Vec<String>) -> Vec<(Vec<String>, Option<String>)> {
    let with = |s: &syn::Ident| {
        let mut p = prefix.clone();
        p.push(s.to_string());
        p
    };
    match tree {
        UseTree::Path(p) => leaves(&p.tree, with(&p.ident)),
        UseTree::Name(n) => {
            if n.ident == "self" {
                let name = prefix.last().cloned();
                vec![(prefix, name)]
            } else {
                vec![(with(&n.ident), Some(n.ident.to_string()))]
            }
        }
        UseTree::Rename(r) => vec![(with(&r.ident), Some(r.rename.to_string()))],
        UseTree::Glob(_) => vec![(prefix, None)],
        UseTree::Group(g) => g.items.iter().flat_map(|t| leaves(t, prefix.clone())).collect(),
    }
}

fn item_name(item: &Item) -> Option<String> {
    Some(match item {
        Item::Const(i) => i.ident.to_string(),
        Item::Enum(i) => i.ident.to_string(),
        Item::Fn(i) => i.sig.ident.to_string(),
        Item::Mod(i) => i.ident.to_string(),
        Item::Static(i) => i.ident.to_string(),
        Item::Struct(i) => i.ident.to_string(),
        Item::Trait(i) => i.ident.to_string(),
        Item::Type(i) => i.ident.to_string(),
        Item::Union(i) => i.ident.to_string(),
        _ => return None,
    })
}

fn item_vis(item: &Item) -> Option<&Visibility> {
    Some(match item {
        Item::Const(i) => &i.vis,
        Item::Enum(i) => &i.vis,
        Item::Fn(i) => &i.vis,
        Item::Static(i) => &i.vis,
        Item::Struct(i) => &i.vis,
        Item::Trait(i) => &i.vis,
        Item::Type(i) => &i.vis,
        Item::Union(i) => &i.vis,
        _ => return None,
    })
}

fn item_attrs(item: &Item) -> &[syn::Attribute] {
    match item {
        Item::Const(i) => &i.attrs,
        Item::Enum(i) => &i.attrs,
        Item::Fn(i) => &i.attrs,
        Item::Impl(i) => &i.attrs,
        Item::Mod(i) => &i.attrs,
        Item::Static(i) => &i.attrs,
        Item::Struct(i) => &i.attrs,
        Item::Trait(i) => &i.attrs,
        Item::Type(i) => &i.attrs,
        Item::Union(i) => &i.attrs,
        Item::Use(i) => &i.attrs,
        _ => &[],
    }
}

fn kind(item: &Item) -> &'static str {
    match item {
        Item::Const(_) => "const",
        Item::Enum(_) => "enum",
        Item::Fn(_) => "fn",
        Item::Static(_) => "static",
        Item::Struct(_) => "struct",
        Item::Trait(_) => "trait",
        Item::Type(_) => "type",
        Item::Union(_) => "union",
        _ => "item",
    }
}

/// The sorted listing of the public API of the crate whose `lib.rs` is given.
fn listing(lib: &Path) -> String {
    let krate = Crate::read(lib);
    let mut out = BTreeSet::new();
    krate.list(0, "dualspectra", &mut out, &mut HashSet::new());
    out.into_iter().map(|l| l + "\n").collect()
}

fn manifest() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn public_api_matches_the_committed_listing() {
    let now = listing(&manifest().join("src/lib.rs"));
    let committed = std::fs::read_to_string(manifest().join("public-api.txt")).unwrap_or_default();
    if now != committed {
        let (a, b): (BTreeSet<&str>, BTreeSet<&str>) = (committed.lines().collect(), now.lines().collect());
        let removed: Vec<String> = a.difference(&b).map(|l| format!("- {l}")).collect();
        let added: Vec<String> = b.difference(&a).map(|l| format!("+ {l}")).collect();
        panic!(
            "the public API differs from rust/dualspectra/public-api.txt:\n{}\n{}\n\nIf the change is \
             deliberate, regenerate the listing with\n  cargo test -p dualspectra --test public_api -- \
             --ignored bless_public_api\nand commit it.",
            removed.join("\n"),
            added.join("\n")
        );
    }
    // The listing reads the real crate: the main entry points are in it.
    for line in ["struct dualspectra::Localizer", "fn dualspectra::localize", "struct dualspectra::TriMesh"] {
        assert!(now.lines().any(|l| l == line), "{line} missing from the listing");
    }
}

/// Rewrites `public-api.txt` from the sources (run it after a deliberate API change).
#[test]
#[ignore = "rewrites public-api.txt; run after a deliberate API change"]
fn bless_public_api() {
    std::fs::write(manifest().join("public-api.txt"), listing(&manifest().join("src/lib.rs"))).unwrap();
}
