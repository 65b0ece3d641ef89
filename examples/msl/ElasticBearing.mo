within Modelica.Mechanics.Rotational.Examples;
model ElasticBearing "Example to show possible usage of support flange"
  // Tolerance 1e-9: MSL's springDamper.w_rel(nominal=1e-4) scales the reference run's error
  // control on that small oscillation; stiction's Tolerance is relative to one scale for all.
  extends Modelica.Icons.Example;
  Rotational.Components.Inertia shaft(phi(fixed=true, start=0), J=1, w(fixed=true, start=0));
  Rotational.Components.Inertia load(J=50, w(fixed=true, start=0));
  Rotational.Components.Spring spring(c=1e3, phi_rel(fixed=true));
  Rotational.Components.Fixed fixed;
  Rotational.Components.SpringDamper springDamper(c=1e5, d=5, phi_rel(fixed=true), w_rel(fixed=true, nominal=1e-4));
  Rotational.Sources.Torque torque(useSupport=true);
  Modelica.Blocks.Sources.Ramp ramp(duration=5, height=100);
  Rotational.Components.IdealGear idealGear(ratio=3, useSupport=true);
  Rotational.Components.Inertia housing(J=5);
  Sensors.MultiSensor multiSensor;
equation
  connect(torque.flange, shaft.flange_a);
  connect(spring.flange_b, load.flange_a);
  connect(springDamper.flange_a, fixed.flange);
  connect(shaft.flange_b, idealGear.flange_a);
  connect(idealGear.flange_b, spring.flange_a);
  connect(idealGear.support, housing.flange_b);
  connect(ramp.y, torque.tau);
  connect(fixed.flange, torque.support);
  connect(housing.flange_a, multiSensor.flange_b);
  connect(multiSensor.flange_a, springDamper.flange_b);
  annotation (experiment(StopTime=10, Interval=0.01, Tolerance=1e-09), Documentation(info="<html>
<p>The gearbox is not fixed rigidly to the ground but through a spring-damper; a MultiSensor
between the housing and that spring-damper measures the bearing's torque, speed and power.</p>
</html>"));
end ElasticBearing;
