within Modelica.Mechanics.Rotational.Examples;
model RollingWheel "Demonstrate coupling Rotational - Translational"
  extends Modelica.Icons.Example;
  Rotational.Components.IdealRollingWheel idealRollingWheel(radius=1);
  Rotational.Components.Inertia inertia(
    J=1,
    phi(fixed=true, start=0),
    w(fixed=true, start=0));
  Rotational.Sources.TorqueStep torqueStep(
    stepTorque=10,
    offsetTorque=0,
    startTime=0.1,
    useSupport=false);
  Translational.Components.Mass mass(L=0, m=1);
  Translational.Sources.QuadraticSpeedDependentForce
    quadraticSpeedDependentForce(
    f_nominal=-10,
    ForceDirection=false,
    v_nominal=5);
equation

  connect(torqueStep.flange, inertia.flange_a);
  connect(inertia.flange_b, idealRollingWheel.flangeR);
  connect(idealRollingWheel.flangeT, mass.flange_a) annotation (Line(
      points={{10,0},{20,0}}, color={0,127,0}));
  connect(quadraticSpeedDependentForce.flange, mass.flange_b);
  annotation (
    Documentation(info="<html>
<p>stiction's test model of MSL's RollingWheel example, in MSL's own style.</p>
</html>",
      figures = {
        Figure(
          title = "Velocities",
          identifier = "fd586",
          preferred = true,
          plots = {
            Plot(
              curves = {
                Curve(y = inertia.w, legend = "Angular velocity of inertia connected to the wheel")
              }
            ),
            Plot(
              curves = {
                Curve(y = mass.v, legend = "Velocity of inertia connected to the wheel")
              }
            )
          }
        )
      }
    ),
       experiment(StopTime=5.0, Interval=0.001));
end RollingWheel;
