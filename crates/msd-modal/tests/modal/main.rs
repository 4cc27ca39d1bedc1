//! Integration tests of msd-modal: one test binary, one module per topic: several modes
//! from one FRF (the diagram, the selection, the polish and its intervals), a roving
//! hammer on a beam (a set with common poles and shapes), the real hammer test.

mod beam;
mod building;
mod efdd;
mod modes;
mod oma;
mod real_hammer;
mod set_noise;
