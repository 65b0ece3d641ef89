within Modelica.Mechanics.Rotational.Examples;
model LossyGearDemo2 "Example to show combination of LossyGear and BearingFriction"
  extends Modelica.Icons.Example;
  SI.Power PowerLoss=gear.flange_a.tau*der(gear.flange_a.phi) + gear.flange_b.tau*der(gear.flange_b.phi)
    "Power lost in the gear";
  Rotational.Components.LossyGear gear(
    ratio=2,
    lossTable=[0, 0.5, 0.5, 0, 0],
    useSupport=true)
    annotation (Placement(transformation(extent={{-10,-10},{10,10}})));
  Rotational.Components.Inertia Inertia1(J=1)
    annotation (Placement(transformation(extent={{-40,-10},{-20,10}})));
  Rotational.Components.Inertia Inertia2(
    J=1.5,
    phi(start=0, fixed=true, nominal=1e-4),
    w(start=0, fixed=true, nominal=0.001))
    annotation (Placement(transformation(extent={{20,-10},{40,10}})));
  Rotational.Sources.Torque torque1(useSupport=true)
    annotation (Placement(transformation(extent={{-100,-10},{-80,10}})));
  Rotational.Sources.Torque torque2(useSupport=true)
    annotation (Placement(transformation(extent={{70,-10},{50,10}})));
  Modelica.Blocks.Sources.Sine DriveSine(amplitude=10, f=1)
    annotation (Placement(transformation(extent={{-130,-10},{-110,10}})));
  Modelica.Blocks.Sources.Ramp load(
    height=5,
    duration=2,
    offset=-10)
    annotation (Placement(transformation(extent={{100,-10},{80,10}})));
  Rotational.Components.BearingFriction bearingFriction(tau_pos=[0, 0.5; 1, 1], useSupport=true)
    annotation (Placement(transformation(extent={{-70,-10},{-50,10}})));
  Rotational.Components.Fixed fixed
    annotation (Placement(transformation(extent={{-10,-50},{10,-30}})));
equation
  connect(torque2.flange, Inertia2.flange_b) annotation (Line(points={{50,0},{40,0}}));
  connect(Inertia2.flange_a, gear.flange_b) annotation (Line(points={{20,0},{10,0}}));
  connect(gear.flange_a, Inertia1.flange_b) annotation (Line(points={{-10,0},{-20,0}}));
  connect(Inertia1.flange_a, bearingFriction.flange_b) annotation (Line(points={{-40,0},{-50,0}}));
  connect(bearingFriction.flange_a, torque1.flange) annotation (Line(points={{-70,0},{-80,0}}));
  connect(DriveSine.y, torque1.tau) annotation (Line(points={{-109,0},{-102,0}}, color={0,0,127}));
  connect(load.y, torque2.tau) annotation (Line(points={{79,0},{72,0}}, color={0,0,127}));
  connect(fixed.flange, gear.support) annotation (Line(points={{0,-40},{0,-10}}));
  connect(fixed.flange, torque2.support) annotation (Line(points={{0,-40},{60,-40},{60,-10}}));
  connect(fixed.flange, bearingFriction.support) annotation (Line(points={{0,-40},{-60,-40},{-60,-10}}));
  connect(fixed.flange, torque1.support) annotation (Line(points={{0,-40},{-90,-40},{-90,-10}}));
  annotation (experiment(StopTime=0.5, Interval=0.0005, Tolerance=1e-06), Documentation(info="<html>
<p>This model contains bearing friction and gear friction (= efficiency). If both friction
models are stuck, there is no unique solution; a reliable simulator has to handle it.</p>
</html>"));
end LossyGearDemo2;
