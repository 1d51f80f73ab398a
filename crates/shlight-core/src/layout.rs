//! Environment-map layouts (equirect, cube cross, strip, angular map, mirror
//! ball): texel directions, exact texel solid angles, lookups, projection.
