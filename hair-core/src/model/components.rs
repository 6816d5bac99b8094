//! [`Component`]: the parts of a strand model that can run, and [`ComponentSet`], which of them a
//! solver runs, for reports. A set, not strings, so a host can ask `contains(Component::Goal)`
//! and a report lists them in one fixed order.

#[cfg(feature = "serde")]
use serde::{Serialize, Serializer};

/// One part of a strand model. The order of the variants is the order reports list them in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Component {
    /// Stretch springs between neighbouring points (mass-spring).
    Stretch,
    /// Bending springs towards the rest direction (mass-spring).
    Bend,
    /// Goal springs towards the animated rest shape.
    Goal,
    /// Gravity.
    Gravity,
    /// Linear air drag.
    AirDrag,
    /// The damping sub-loop on relative velocity along each segment.
    Damping,
    /// Provot's strain limit with `max_strain > 0`.
    StrainLimit,
    /// The strain limit at `max_strain = 0`: inextensible strands.
    Inextensibility,
    /// Seed 002's inextensibility projection after each substep.
    InextensibilityProjection,
    /// The rod's bending of an elliptical cross-section.
    RodBending,
    /// The rod's quasistatic twist.
    QuasistaticTwist,
    /// The rod's inextensibility projection.
    RodProjection,
    /// The strips' post-step passes (strain limit, root angle limiter, head push-out).
    StripLimits,
    /// Voxel hair–hair friction.
    HairHairFriction,
    /// Voxel hair–hair repulsion.
    HairHairRepulsion,
    /// A wind field.
    Wind,
    /// A vortex field.
    Vortex,
    /// A turbulence field.
    Turbulence,
    /// A drag field.
    DragField,
    /// A point force field.
    ForceField,
    /// Hair–object contacts.
    Contacts,
}

impl Component {
    /// Every component, in report order.
    pub const ALL: [Component; 21] = [
        Component::Stretch,
        Component::Bend,
        Component::Goal,
        Component::Gravity,
        Component::AirDrag,
        Component::Damping,
        Component::StrainLimit,
        Component::Inextensibility,
        Component::InextensibilityProjection,
        Component::RodBending,
        Component::QuasistaticTwist,
        Component::RodProjection,
        Component::StripLimits,
        Component::HairHairFriction,
        Component::HairHairRepulsion,
        Component::Wind,
        Component::Vortex,
        Component::Turbulence,
        Component::DragField,
        Component::ForceField,
        Component::Contacts,
    ];

    /// The name reports print (and caches store).
    pub fn name(self) -> &'static str {
        match self {
            Component::Stretch => "stretch",
            Component::Bend => "bend",
            Component::Goal => "goal",
            Component::Gravity => "gravity",
            Component::AirDrag => "air drag",
            Component::Damping => "damping",
            Component::StrainLimit => "strain limit",
            Component::Inextensibility => "inextensibility",
            Component::InextensibilityProjection => "inextensibility projection",
            Component::RodBending => "rod bending (elliptical section)",
            Component::QuasistaticTwist => "quasistatic twist",
            Component::RodProjection => "inextensibility (projection)",
            Component::StripLimits => "strip limits",
            Component::HairHairFriction => "hair-hair friction",
            Component::HairHairRepulsion => "hair-hair repulsion",
            Component::Wind => "wind",
            Component::Vortex => "vortex",
            Component::Turbulence => "turbulence",
            Component::DragField => "drag field",
            Component::ForceField => "force field",
            Component::Contacts => "contacts",
        }
    }

    fn bit(self) -> u32 {
        1 << self as u8
    }
}

impl std::fmt::Display for Component {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(feature = "serde")]
impl Serialize for Component {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// A set of [`Component`]s; iterates (and serialises, as a list of names) in report order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct ComponentSet(u32);

impl ComponentSet {
    /// The empty set.
    pub fn new() -> Self {
        Self(0)
    }

    /// Adds `c`.
    pub fn insert(&mut self, c: Component) {
        self.0 |= c.bit();
    }

    /// Does the set hold `c`?
    pub fn contains(&self, c: Component) -> bool {
        self.0 & c.bit() != 0
    }

    /// True when nothing runs.
    pub fn is_empty(&self) -> bool {
        self.0 == 0
    }

    /// The components, in report order.
    pub fn iter(&self) -> impl Iterator<Item = Component> + '_ {
        Component::ALL.into_iter().filter(|c| self.contains(*c))
    }

    /// The names, in report order.
    pub fn names(&self) -> Vec<&'static str> {
        self.iter().map(Component::name).collect()
    }
}

impl FromIterator<Component> for ComponentSet {
    fn from_iter<I: IntoIterator<Item = Component>>(iter: I) -> Self {
        let mut set = ComponentSet::new();
        for c in iter {
            set.insert(c);
        }
        set
    }
}

impl std::fmt::Display for ComponentSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.names().join(", "))
    }
}

#[cfg(feature = "serde")]
impl Serialize for ComponentSet {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.iter())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_component_has_its_own_bit_and_lists_in_declaration_order() {
        let all: ComponentSet = Component::ALL.into_iter().collect();
        assert_eq!(all.iter().count(), Component::ALL.len());
        for (i, c) in Component::ALL.iter().enumerate() {
            assert_eq!(*c as usize, i, "ALL must follow the declaration order");
        }
        let mut set = ComponentSet::new();
        set.insert(Component::Contacts);
        set.insert(Component::Stretch);
        assert_eq!(set.names(), vec!["stretch", "contacts"]);
        assert!(!set.contains(Component::Bend));
    }
}
