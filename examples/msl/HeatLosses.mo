within Modelica.Mechanics.Rotational.Examples;
model HeatLosses "Demonstrate the modeling of heat losses"
  extends Modelica.Icons.Example;
  Blocks.Sources.Sine sine(f=5, amplitude=20)
    annotation (Placement(transformation(extent={{-100,-10},{-80,10}})));
  Sources.Torque torque
    annotation (Placement(transformation(extent={{-70,-10},{-50,10}})));
  Components.Inertia inertia1(
    J=2,
    phi(fixed=true, start=0),
    w(fixed=true, start=0))
    annotation (Placement(transformation(extent={{-40,-10},{-20,10}})));
  Components.Damper damper(d=10, useHeatPort=true)
    annotation (Placement(transformation(origin={-10,-20}, extent={{-10,-10},{10,10}}, rotation=90)));
  Components.Fixed fixed
    annotation (Placement(transformation(extent={{-20,-50},{0,-30}})));
  Thermal.HeatTransfer.Components.Convection convection
    annotation (Placement(transformation(extent={{10,-80},{-10,-60}})));
  Thermal.HeatTransfer.Celsius.FixedTemperature TAmbient(T=25)
    "Ambient temperature"
    annotation (Placement(transformation(extent={{-40,-80},{-20,-60}})));
  Blocks.Sources.Constant const(k=20)
    annotation (Placement(transformation(origin={0,-40}, extent={{-10,-10},{10,10}}, rotation=270)));
  Components.SpringDamper springDamper(c=1e4, d=20, useHeatPort=true)
    annotation (Placement(transformation(extent={{-10,-10},{10,10}})));
  Components.Inertia inertia2(
    J=2,
    phi(fixed=true, start=0),
    w(fixed=true, start=0))
    annotation (Placement(transformation(extent={{20,-10},{40,10}})));
  Components.ElastoBacklash elastoBacklash(
    c=1e5,
    d=100,
    b=0.001,
    useHeatPort=true)
    annotation (Placement(transformation(extent={{50,-10},{70,10}})));
  Components.Inertia inertia3(
    J=2,
    phi(fixed=true, start=0),
    w(fixed=true, start=0))
    annotation (Placement(transformation(extent={{80,-10},{100,10}})));
  Components.BearingFriction bearingFriction(useHeatPort=true)
    annotation (Placement(transformation(extent={{110,-10},{130,10}})));
  Components.Spring spring3(c=1e4)
    annotation (Placement(transformation(extent={{140,-10},{160,10}})));
  Components.Inertia inertia4(
    J=2,
    phi(fixed=true, start=0),
    w(fixed=true, start=0))
    annotation (Placement(transformation(extent={{170,-10},{190,10}})));
  Components.LossyGear lossyGear(
    ratio=2,
    lossTable=[0, 0.8, 0.8, 1, 1; 1, 0.7, 0.7, 2, 2],
    useHeatPort=true)
    annotation (Placement(transformation(extent={{200,-10},{220,10}})));
  Components.Clutch clutch(
    fn_max=10,
    useHeatPort=true,
    phi_rel(fixed=true),
    w_rel(fixed=true))
    annotation (Placement(transformation(extent={{230,-10},{250,10}})));
  Components.Inertia inertia5(J=2)
    annotation (Placement(transformation(extent={{260,-10},{280,10}})));
  Blocks.Sources.Sine sine2(f=0.2, amplitude=1)
    annotation (Placement(transformation(extent={{200,40},{220,60}})));
  Components.Inertia inertia6(J=2)
    annotation (Placement(transformation(extent={{320,-10},{340,10}})));
  Components.OneWayClutch oneWayClutch(
    fn_max=1,
    useHeatPort=true,
    phi_rel(fixed=true),
    w_rel(fixed=true),
    startForward(fixed=true, start=false),
    stuck(fixed=true, start=false))
    annotation (Placement(transformation(extent={{290,-10},{310,10}})));
  Components.Brake brake(fn_max=2, useHeatPort=true)
    annotation (Placement(transformation(extent={{350,-10},{370,10}})));
equation
  connect(sine.y, torque.tau) annotation (Line(points={{-79,0},{-72,0}}, color={0,0,127}));
  connect(torque.flange, inertia1.flange_a) annotation (Line(points={{-50,0},{-40,0}}));
  connect(inertia1.flange_b, damper.flange_b) annotation (Line(points={{-20,0},{-10,0},{-10,-10}}));
  connect(damper.flange_a, fixed.flange) annotation (Line(points={{-10,-30},{-10,-40}}));
  connect(inertia1.flange_b, springDamper.flange_a) annotation (Line(points={{-20,0},{-10,0}}));
  connect(springDamper.flange_b, inertia2.flange_a) annotation (Line(points={{10,0},{20,0}}));
  connect(inertia2.flange_b, elastoBacklash.flange_a) annotation (Line(points={{40,0},{50,0}}));
  connect(elastoBacklash.flange_b, inertia3.flange_a) annotation (Line(points={{70,0},{80,0}}));
  connect(inertia3.flange_b, bearingFriction.flange_a) annotation (Line(points={{100,0},{110,0}}));
  connect(bearingFriction.flange_b, spring3.flange_a) annotation (Line(points={{130,0},{140,0}}));
  connect(spring3.flange_b, inertia4.flange_a) annotation (Line(points={{160,0},{170,0}}));
  connect(inertia4.flange_b, lossyGear.flange_a) annotation (Line(points={{190,0},{200,0}}));
  connect(lossyGear.flange_b, clutch.flange_a) annotation (Line(points={{220,0},{230,0}}));
  connect(clutch.flange_b, inertia5.flange_a) annotation (Line(points={{250,0},{260,0}}));
  connect(inertia5.flange_b, oneWayClutch.flange_a) annotation (Line(points={{280,0},{290,0}}));
  connect(oneWayClutch.flange_b, inertia6.flange_a) annotation (Line(points={{310,0},{320,0}}));
  connect(inertia6.flange_b, brake.flange_a) annotation (Line(points={{340,0},{350,0}}));
  connect(sine2.y, clutch.f_normalized) annotation (Line(points={{221,50},{240,50},{240,11}}, color={0,0,127}));
  connect(sine2.y, oneWayClutch.f_normalized) annotation (Line(points={{221,50},{300,50},{300,11}}, color={0,0,127}));
  connect(sine2.y, brake.f_normalized) annotation (Line(points={{221,50},{360,50},{360,11}}, color={0,0,127}));
  connect(const.y, convection.Gc) annotation (Line(points={{0,-51},{0,-60}}, color={0,0,127}));
  connect(TAmbient.port, convection.fluid) annotation (Line(points={{-20,-70},{-10,-70}}, color={191,0,0}));
  connect(convection.solid, damper.heatPort) annotation (Line(points={{10,-70},{20,-70},{20,-20},{0,-20}}, color={191,0,0}));
  connect(convection.solid, springDamper.heatPort) annotation (Line(points={{10,-70},{20,-70},{20,-10},{-10,-10}}, color={191,0,0}));
  connect(convection.solid, elastoBacklash.heatPort) annotation (Line(points={{10,-70},{50,-70},{50,-10}}, color={191,0,0}));
  connect(convection.solid, bearingFriction.heatPort) annotation (Line(points={{10,-70},{110,-70},{110,-10}}, color={191,0,0}));
  connect(convection.solid, lossyGear.heatPort) annotation (Line(points={{10,-70},{200,-70},{200,-10}}, color={191,0,0}));
  connect(convection.solid, clutch.heatPort) annotation (Line(points={{10,-70},{230,-70},{230,-10}}, color={191,0,0}));
  connect(convection.solid, oneWayClutch.heatPort) annotation (Line(points={{10,-70},{290,-70},{290,-10}}, color={191,0,0}));
  connect(convection.solid, brake.heatPort) annotation (Line(points={{10,-70},{350,-70},{350,-10}}, color={191,0,0}));
  annotation (experiment(StopTime=1.0, Interval=5e-05, Tolerance=1e-06), Documentation(info="<html>
<p>This model demonstrates how to model the dissipated power of a drive train by enabling the
heatPort of all components and connecting these heatPorts to a convection element. The total
heat flow generated by the elements of the drive train and transferred to the environment
is present in variable convection.fluid.</p>
</html>"));
end HeatLosses;
