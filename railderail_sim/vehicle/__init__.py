"""CRH3 vehicle-track model: state layout (`layout`), equations of motion (`dynamics`), stepper
(`integrator`), linearisation (`linear`), model building (`assemble`) and the simulate() API
(`simulate`). Import the modules themselves: this file imports nothing, so that e.g.
`railderail_sim.vehicle.layout` loads without the model."""
