within Modelica.Mechanics.Rotational.Examples;
model OneWayClutchDisengaged "Drive train with disengaged one-way clutch"
  extends Modelica.Icons.Example;
  Rotational.Components.Inertia inertiaIn(
    J=1,
    phi(start=0, fixed=true),
    w(start=-0.5, fixed=true))
    annotation (Placement(transformation(extent={{-40,-10},{-20,10}})));
  Rotational.Components.Inertia inertiaOut(
    J=1,
    phi(start=0, fixed=true),
    w(start=0, fixed=true))
    annotation (Placement(transformation(extent={{20,-10},{40,10}})));
  Rotational.Components.OneWayClutch oneWayClutch(
    peak=25,
    fn_max=3,
    startForward(fixed=true, start=false),
    stuck(fixed=true, start=false))
    annotation (Placement(transformation(extent={{-10,-10},{10,10}})));
  Rotational.Sources.Torque torque
    annotation (Placement(transformation(extent={{-70,-10},{-50,10}})));
  Rotational.Sources.ConstantTorque torqueLoad(tau_constant=-0.3)
    annotation (Placement(transformation(extent={{70,-10},{50,10}})));
  Modelica.Blocks.Sources.Sine signalTorque(amplitude=10, offset=-torqueLoad.tau_constant, f=2)
    annotation (Placement(transformation(extent={{-100,-10},{-80,10}})));
  Modelica.Blocks.Sources.Constant signalEngagement(k=0)
    annotation (Placement(transformation(extent={{-40,30},{-20,50}})));
equation
  connect(signalTorque.y, torque.tau) annotation (Line(points={{-79,0},{-72,0}}, color={0,0,127}));
  connect(torque.flange, inertiaIn.flange_a) annotation (Line(points={{-50,0},{-40,0}}));
  connect(inertiaIn.flange_b, oneWayClutch.flange_a) annotation (Line(points={{-20,0},{-10,0}}));
  connect(oneWayClutch.flange_b, inertiaOut.flange_a) annotation (Line(points={{10,0},{20,0}}));
  connect(inertiaOut.flange_b, torqueLoad.flange) annotation (Line(points={{40,0},{50,0}}));
  connect(signalEngagement.y, oneWayClutch.f_normalized) annotation (Line(points={{-19,40},{0,40},{0,11}}, color={0,0,127}));
  annotation (experiment(StopTime=2, Interval=0.0005, Tolerance=1e-06), Documentation(info="<html>
<p>The freewheel alone: the clutch of the OneWayClutch is never engaged.</p>
</html>"));
end OneWayClutchDisengaged;
