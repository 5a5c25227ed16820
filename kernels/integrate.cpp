// The one instantiation of the integrators (see the note in integrate.hpp).
#include "integrate.hpp"

namespace kdem {

template void kick_and_drift<IsotropicRotation>(const ParticleViews&, double);
template void kick_and_drift<RigidBodyRotation>(const ParticleViews&, double);
template void kick<IsotropicRotation>(const ParticleViews&, double);
template void kick<RigidBodyRotation>(const ParticleViews&, double);

} // namespace kdem
