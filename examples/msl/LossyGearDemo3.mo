within Modelica.Mechanics.Rotational.Examples;
model LossyGearDemo3 "Example that failed in the previous version of the LossyGear model"
  extends Modelica.Icons.Example;
  Rotational.Components.LossyGear gear(ratio=1, lossTable=[0, 0.25, 0.25, 0.625, 2.5])
    annotation (Placement(transformation(extent={{-10,-10},{10,10}})));
  Rotational.Components.Inertia Inertia1(J=0.001, w(start=10))
    annotation (Placement(transformation(extent={{-40,-10},{-20,10}})));
  Rotational.Components.Inertia Inertia2(
    J=0.001,
    phi(fixed=true, start=0),
    w(fixed=true, start=10))
    annotation (Placement(transformation(extent={{20,-10},{40,10}})));
  Rotational.Sources.Torque torque1
    annotation (Placement(transformation(extent={{-70,-10},{-50,10}})));
  Rotational.Sources.Torque torque2
    annotation (Placement(transformation(extent={{70,-10},{50,10}})));
  Modelica.Blocks.Sources.Step step(height=0)
    annotation (Placement(transformation(extent={{-100,-10},{-80,10}})));
  Modelica.Blocks.Sources.Step step1(
    startTime=0.5,
    height=1,
    offset=0)
    annotation (Placement(transformation(extent={{100,-10},{80,10}})));
equation
  connect(torque1.flange, Inertia1.flange_a) annotation (Line(points={{-50,0},{-40,0}}));
  connect(Inertia1.flange_b, gear.flange_a) annotation (Line(points={{-20,0},{-10,0}}));
  connect(gear.flange_b, Inertia2.flange_a) annotation (Line(points={{10,0},{20,0}}));
  connect(Inertia2.flange_b, torque2.flange) annotation (Line(points={{40,0},{50,0}}));
  connect(step.y, torque1.tau) annotation (Line(points={{-79,0},{-72,0}}, color={0,0,127}));
  connect(step1.y, torque2.tau) annotation (Line(points={{79,0},{72,0}}, color={0,0,127}));
  annotation (experiment(StopTime=1, Interval=0.001, Tolerance=1e-06), Documentation(info="<html>
<p>The driving side of the gear is not obvious here; older LossyGear versions failed with no
convergence of the event iteration.</p>
</html>"));
end LossyGearDemo3;
