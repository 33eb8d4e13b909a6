//! The scheme library: every table of the built-in catalogue
//! (`tableau/catalogue/*.toml`) as a scheme type, declared with `butcher!`
//! reading the catalogue file, so each table is written once in the
//! repository and `symlab check --builtin ID` analyses the very same table.
//! Each type's claims are the ones its file states, verified at compile
//! time; its doc comment names the literature source.
//!
//! Implicit tables (Gauss–Legendre, Radau, Lobatto IIIA/B/C, the paper's
//! DIRKs, implicit pairs) step too: their stage equations are solved by
//! [`implicit::step`](crate::implicit::step) (simplified Newton with faer's
//! LU, or fixed-point iteration where the system has no Jacobian; DIRK
//! tables stage by stage), with the table as a constant.

use crate::butcher;
use crate::scheme::{Info, Scheme};
butcher! {
    pub ExplicitEuler { from: "euler" }
}
butcher! {
    pub Heun { from: "heun" }
}
butcher! {
    pub Rk4 { from: "rk4" }
}
butcher! {
    pub Rk38 { from: "rk38" }
}
butcher! {
    pub ImplicitEuler { from: "implicit-euler" }
}
butcher! {
    pub ImplicitMidpoint { from: "midpoint" }
}
butcher! {
    pub GaussLegendre1 { from: "gauss1" }
}
butcher! {
    pub GaussLegendre2 { from: "gauss2" }
}
butcher! {
    pub GaussLegendre3 { from: "gauss3" }
}
butcher! {
    pub RadauIIA2 { from: "radau2a-2" }
}
butcher! {
    pub RadauIIA3 { from: "radau2a-3" }
}
butcher! {
    pub LobattoIIIA2 { from: "lobatto3a-2" }
}
butcher! {
    pub LobattoIIIA3 { from: "lobatto3a-3" }
}
butcher! {
    pub LobattoIIIB2 { from: "lobatto3b-2" }
}
butcher! {
    pub LobattoIIIB3 { from: "lobatto3b-3" }
}
butcher! {
    pub LobattoIIIC2 { from: "lobatto3c-2" }
}
butcher! {
    pub LobattoIIIC3 { from: "lobatto3c-3" }
}
butcher! {
    pub LobattoIIICStar2 { from: "lobatto3cstar-2" }
}
butcher! {
    pub PaperDirk2 { from: "paper-dirk2" }
}
butcher! {
    pub PaperDirk4 { from: "paper-dirk4" }
}
butcher! {
    pub SymplecticEulerA { from: "symplectic-euler-a" }
}
butcher! {
    pub SymplecticEulerB { from: "symplectic-euler-b" }
}
butcher! {
    pub StormerVerlet { from: "stormer-verlet" }
}
butcher! {
    pub LobattoIIIAIIIB3 { from: "lobatto3a3b-3" }
}
butcher! {
    pub LobattoIIICIIICStar2 { from: "lobatto3c3cstar-2" }
}
butcher! {
    pub Leapfrog { from: "leapfrog" }
}
butcher! {
    pub Ruth3 { from: "ruth3" }
}
butcher! {
    pub ForestRuth { from: "forest-ruth" }
}
butcher! {
    pub CandyRozmus4 { from: "candy-rozmus4" }
}
butcher! {
    pub McLachlanAtela2 { from: "mclachlan-atela2" }
}
butcher! {
    pub McLachlanAtela3 { from: "mclachlan-atela3" }
}
butcher! {
    pub McLachlanAtela4 { from: "mclachlan-atela4" }
}
butcher! {
    pub McLachlanAtela5 { from: "mclachlan-atela5" }
}
butcher! {
    pub CalvoSanzSerna4 { from: "calvo-sanz-serna4" }
}
butcher! {
    pub McLachlan4 { from: "mclachlan4" }
}
butcher! {
    pub Pefrl { from: "pefrl" }
}
butcher! {
    pub McLachlanS5 { from: "mclachlan-s5" }
}
butcher! {
    pub BlanesMoanPrk6 { from: "blanes-moan-prk6" }
}
butcher! {
    pub BlanesMoanPrk10 { from: "blanes-moan-prk10" }
}
butcher! {
    pub BlanesMoanSrkn6b { from: "blanes-moan-srkn6b" }
}
butcher! {
    pub BlanesMoanSrkn11b { from: "blanes-moan-srkn11b" }
}
butcher! {
    pub BlanesMoanSrkn14a { from: "blanes-moan-srkn14a" }
}
butcher! {
    pub Yoshida4 { from: "yoshida4" }
}
butcher! {
    pub Yoshida6 { from: "yoshida6" }
}
butcher! {
    pub KahanLi6 { from: "kahan-li6" }
}
butcher! {
    pub McLachlanSS9 { from: "mclachlan-ss9" }
}
butcher! {
    pub KahanLi8 { from: "kahan-li8" }
}
butcher! {
    pub McLachlan8 { from: "mclachlan8" }
}
butcher! {
    pub SofroniouSpaletta10 { from: "sofroniou-spaletta10" }
}
/// Every library scheme by catalogue id, in catalogue order.
pub const REGISTRY: &[(&str, Info)] = &[
    ("euler", <ExplicitEuler as Scheme>::INFO),
    ("heun", <Heun as Scheme>::INFO),
    ("rk4", <Rk4 as Scheme>::INFO),
    ("rk38", <Rk38 as Scheme>::INFO),
    ("implicit-euler", <ImplicitEuler as Scheme>::INFO),
    ("midpoint", <ImplicitMidpoint as Scheme>::INFO),
    ("gauss1", <GaussLegendre1 as Scheme>::INFO),
    ("gauss2", <GaussLegendre2 as Scheme>::INFO),
    ("gauss3", <GaussLegendre3 as Scheme>::INFO),
    ("radau2a-2", <RadauIIA2 as Scheme>::INFO),
    ("radau2a-3", <RadauIIA3 as Scheme>::INFO),
    ("lobatto3a-2", <LobattoIIIA2 as Scheme>::INFO),
    ("lobatto3a-3", <LobattoIIIA3 as Scheme>::INFO),
    ("lobatto3b-2", <LobattoIIIB2 as Scheme>::INFO),
    ("lobatto3b-3", <LobattoIIIB3 as Scheme>::INFO),
    ("lobatto3c-2", <LobattoIIIC2 as Scheme>::INFO),
    ("lobatto3c-3", <LobattoIIIC3 as Scheme>::INFO),
    ("lobatto3cstar-2", <LobattoIIICStar2 as Scheme>::INFO),
    ("paper-dirk2", <PaperDirk2 as Scheme>::INFO),
    ("paper-dirk4", <PaperDirk4 as Scheme>::INFO),
    ("symplectic-euler-a", <SymplecticEulerA as Scheme>::INFO),
    ("symplectic-euler-b", <SymplecticEulerB as Scheme>::INFO),
    ("stormer-verlet", <StormerVerlet as Scheme>::INFO),
    ("lobatto3a3b-3", <LobattoIIIAIIIB3 as Scheme>::INFO),
    ("lobatto3c3cstar-2", <LobattoIIICIIICStar2 as Scheme>::INFO),
    ("leapfrog", <Leapfrog as Scheme>::INFO),
    ("ruth3", <Ruth3 as Scheme>::INFO),
    ("forest-ruth", <ForestRuth as Scheme>::INFO),
    ("candy-rozmus4", <CandyRozmus4 as Scheme>::INFO),
    ("mclachlan-atela2", <McLachlanAtela2 as Scheme>::INFO),
    ("mclachlan-atela3", <McLachlanAtela3 as Scheme>::INFO),
    ("mclachlan-atela4", <McLachlanAtela4 as Scheme>::INFO),
    ("mclachlan-atela5", <McLachlanAtela5 as Scheme>::INFO),
    ("calvo-sanz-serna4", <CalvoSanzSerna4 as Scheme>::INFO),
    ("mclachlan4", <McLachlan4 as Scheme>::INFO),
    ("pefrl", <Pefrl as Scheme>::INFO),
    ("mclachlan-s5", <McLachlanS5 as Scheme>::INFO),
    ("blanes-moan-prk6", <BlanesMoanPrk6 as Scheme>::INFO),
    ("blanes-moan-prk10", <BlanesMoanPrk10 as Scheme>::INFO),
    ("blanes-moan-srkn6b", <BlanesMoanSrkn6b as Scheme>::INFO),
    ("blanes-moan-srkn11b", <BlanesMoanSrkn11b as Scheme>::INFO),
    ("blanes-moan-srkn14a", <BlanesMoanSrkn14a as Scheme>::INFO),
    ("yoshida4", <Yoshida4 as Scheme>::INFO),
    ("yoshida6", <Yoshida6 as Scheme>::INFO),
    ("kahan-li6", <KahanLi6 as Scheme>::INFO),
    ("mclachlan-ss9", <McLachlanSS9 as Scheme>::INFO),
    ("kahan-li8", <KahanLi8 as Scheme>::INFO),
    ("mclachlan8", <McLachlan8 as Scheme>::INFO),
    (
        "sofroniou-spaletta10",
        <SofroniouSpaletta10 as Scheme>::INFO,
    ),
];

/// The facts of a library scheme by catalogue id.
pub fn info(id: &str) -> Option<&'static Info> {
    REGISTRY.iter().find(|(k, _)| *k == id).map(|(_, i)| i)
}
