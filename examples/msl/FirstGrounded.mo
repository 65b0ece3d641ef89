within Modelica.Mechanics.Rotational.Examples;
model FirstGrounded
  "First example: simple drive train with grounded elements"
  extends Modelica.Icons.Example;
  parameter Modelica.SIunits.Torque amplitude=10
    "Amplitude of driving torque";
  parameter SI.Frequency f=5 "Frequency of driving torque";
  parameter SI.Inertia Jmotor(min=0) = 0.1 "Motor inertia";
  parameter SI.Inertia Jload(min=0) = 2 "Load inertia";
  parameter Real ratio=10 "Gear ratio";
  parameter Real damping=10 "Damping in bearing of gear";

  Rotational.Components.Fixed fixed
    annotation (Placement(transformation(extent={{38,-48},{54,-32}})));
  Rotational.Sources.Torque torque(useSupport=false)
    annotation (Placement(transformation(extent={{-68,-8},{-52,8}})));
  Rotational.Components.Inertia inertia1(J=Jmotor);
  Rotational.Components.IdealGear idealGear(ratio=ratio, useSupport=false);
  Rotational.Components.Inertia inertia2(
    J=2,
    phi(fixed=true, start=0),
    w(fixed=true, start=0));
  Rotational.Components.Spring spring(c=1.e4, phi_rel(fixed=true));
  Rotational.Components.Inertia inertia3(J=Jload, w(fixed=true, start=0));
  Rotational.Components.Damper damper(d=damping) annotation (Placement(
        transformation(
        origin={46,-22},
        extent={{-8,-8},{8,8}},
        rotation=270)));
  Modelica.Blocks.Sources.Sine sine(amplitude=amplitude, f=f);
equation
  connect(inertia1.flange_b, idealGear.flange_a)
    annotation (Line(points={{-22,0},{-8,0}}));
  connect(idealGear.flange_b, inertia2.flange_a);
  connect(inertia2.flange_b, spring.flange_a);
  connect(spring.flange_b, inertia3.flange_a);
  connect(damper.flange_a, inertia2.flange_b);
  connect(damper.flange_b, fixed.flange);
  connect(sine.y, torque.tau)
    annotation (Line(points={{-81.2,0},{-69.6,0}}, color={0,0,127}));
  connect(torque.flange, inertia1.flange_a) annotation (Line(
      points={{-52,0},{-38,0}}));
  annotation (
    Documentation(info="<html>
<p>stiction's test model of MSL's FirstGrounded example, in MSL's own style.</p>
</html>"),
    experiment(StopTime=1.0, Interval=0.001));
end FirstGrounded;
