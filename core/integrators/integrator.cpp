#include "core/integrators/integrator.h"

#include "core/integrators/classic.h"
#include "core/integrators/progressive.h"

namespace caustica {

std::unique_ptr<Integrator> make_integrator(IntegratorKind kind, const ShadingSetup& setup) {
    switch (kind) {
    case IntegratorKind::progressive: return std::make_unique<ProgressiveIntegrator>(setup);
    case IntegratorKind::classic: break;
    }
    return std::make_unique<ClassicIntegrator>(setup);
}

}  // namespace caustica
